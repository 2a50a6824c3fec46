/* Real-time priorities and affinity a controller asks for, clamped below
 * the coordinator's (sched_clamp.c): for the priority hooks
 * (hooks_sched.c), syscall() by number (hooks_syscall.c), and the
 * attributes of a thread about to be created (hooks_thread.c). */
#ifndef TCS_PRELOAD_SCHED_CLAMP_H
#define TCS_PRELOAD_SCHED_CLAMP_H

#include <pthread.h>
#include <sched.h>

#include "runtime.h"

/* Clamps a real-time request in place: *policy, *prio (said once). */
void tcs_sched_clamp(int *policy, int *prio) TCS_HIDDEN;
/* The system calls, what they ask for clamped (an affinity is granted
 * without moving the controller): 0 or -errno. */
long tcs_sched_setscheduler(long pid, int policy, const struct sched_param *param) TCS_HIDDEN;
long tcs_sched_setattr(long pid, const void *attr, long flags) TCS_HIDDEN;
long tcs_sched_setaffinity(size_t size, const cpu_set_t *set) TCS_HIDDEN;
/* 1 when attr asked for more than a controller may have and was clamped:
 * then restore it after the call with what was saved. */
int tcs_sched_clamp_attr(pthread_attr_t *attr, struct sched_param *saved, int *saved_policy) TCS_HIDDEN;
void tcs_sched_restore_attr(pthread_attr_t *attr, const struct sched_param *saved, int saved_policy) TCS_HIDDEN;

#endif
