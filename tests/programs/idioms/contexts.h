/* The idioms program: the contexts a call is made from, and their signal handlers (contexts.c). */
#ifndef TCS_IDIOMS_CONTEXTS_H
#define TCS_IDIOMS_CONTEXTS_H

#include "idioms.h"

extern volatile int strays;
extern int the_call, the_flow;
extern volatile int done, inside, in_alarm, gave_up;
extern volatile long long handler_runs, nested_runs, inside_hits, lone_calls, goal_calls;
extern long long start_ns;
extern int driver_itimer;
void on_wake(int sig, siginfo_t *si, void *uc);
void on_stray(int sig);
void on(int sig, void (*fn)(int));
void run_main(void);
void run_thread(void);
void run_handler(void);
void run_nested(int by_thread);
void run_fork(void);
void run_vfork(void);

#endif
