/* The idioms program: what a run found (the checks every call uses and their tally) (common.c). */
#ifndef TCS_IDIOMS_COMMON_H
#define TCS_IDIOMS_COMMON_H

#include "idioms.h"

extern const char STATE[];
extern const char TORQUE[];
extern struct flow flows[WHOS];
extern struct stats S;
extern long long seen_mono, seen_real, seen_process, seen_thread, seen_clock, seen_times, seen_times_cpu, seen_rusage;
extern volatile int wakes[WHOS];
extern volatile int wake_code[WHOS], wake_pid[WHOS], wake_value[WHOS];
extern int itimer_use;
long long sum(long long *p, long long n);
void at_most(long long *p, long long v);
void at_least(long long *p, long long v);
long long ns_of(struct timespec t);
struct timespec ts_of(long long ns);
struct timeval tv_of(long long ns);
long long tv_ns(struct timeval t);
long long clock_read(clockid_t id);
long long mono_ns(void);
void fail_with(struct ctx *c, const char *what, int err, int value);
void fail(struct ctx *c, const char *what, int err);
void check(struct ctx *c, int ok, const char *what);
void waited_asked(struct ctx *c, long long t0, long long t1, long long want, long long asked);
void waited(struct ctx *c, long long t0, long long t1, long long want);
void interrupted(void);
int wake_sig(int who);

#endif
