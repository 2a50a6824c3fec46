/* The helper threads of SIGEV_THREAD timers (timer_thread.c). */
#ifndef TCS_PRELOAD_TIMER_THREAD_H
#define TCS_PRELOAD_TIMER_THREAD_H

#include <signal.h>

#include "runtime.h"

/* Starts the helper thread of SIGEV_THREAD timer slot, incarnation gen
 * (sev: the timer's notification): 0 or -errno. */
int tcs_timer_thread_start(int slot, uint32_t gen, const struct sigevent *sev) TCS_HIDDEN;
/* Tells the helpers that a timer changed (each looks at its own again). */
void tcs_timer_threads_poke(void) TCS_HIDDEN;

#endif
