/* The idioms program: the table of calls, and setting up what each needs (table.c). */
#ifndef TCS_IDIOMS_TABLE_H
#define TCS_IDIOMS_TABLE_H

#include "idioms.h"

enum { F_POSIX = 1, F_INTERRUPTED = 2, F_VFORK = 4 };

struct call {
	const char *name;
	void (*fn)(struct ctx *);
	int flags, needs;
};

extern const struct call calls[];
extern const int ncalls;
int call_id(const char *name);
void die(const char *what);
void setup(int who, int id);
void do_call(int id, int who, int role);

#endif
