/* This thread's waits as the rest of the runtime sees them
 * (thread_waits.c): how many blocking hooks it is inside, and whether it
 * waited since it last spun (spin.h). Below the waits themselves (wait.c),
 * so that what only asks (the journal, lazy writes) need not stand on them. */
#ifndef TCS_PRELOAD_THREAD_WAITS_H
#define TCS_PRELOAD_THREAD_WAITS_H

#include "runtime.h"

/* How many blocking hooks this thread is inside: more than one when a
 * signal handler's hook runs inside another's. */
extern __thread int tcs_in_wait TCS_HIDDEN __attribute__((tls_model("initial-exec")));
/* A clock read or empty read since this thread's last wait: the next one
 * is a spin's (spin.c reads and sets it). */
extern __thread int tcs_spun TCS_HIDDEN __attribute__((tls_model("initial-exec")));

/* Enter/leave a blocking hook. tcs_wait_enter() returns 0 when the caller
 * must pass through to the real call (not a controller, or no channel for
 * this thread); a signal handler's hook inside another enters as well. */
int tcs_wait_enter(void) TCS_HIDDEN;
void tcs_wait_leave(void) TCS_HIDDEN;
/* This thread waited: its next clock read or empty read is free. */
void tcs_spin_waited(void) TCS_HIDDEN;

#endif
