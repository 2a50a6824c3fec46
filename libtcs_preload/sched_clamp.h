/* Real-time priorities a controller asks for, clamped below the
 * coordinator's (hooks_sched.c): for syscall() by number, and for the
 * attributes of a thread about to be created. */
#ifndef TCS_PRELOAD_SCHED_CLAMP_H
#define TCS_PRELOAD_SCHED_CLAMP_H

#include <pthread.h>
#include <sched.h>

#include "runtime.h"

long tcs_sched_setscheduler(long pid, int policy, const struct sched_param *param) TCS_HIDDEN;
long tcs_sched_setattr(long pid, const void *attr, long flags) TCS_HIDDEN;
long tcs_sched_setaffinity(size_t size, const cpu_set_t *set) TCS_HIDDEN;
/* 1 when attr asked for more than a controller may have and was clamped:
 * then restore it after the call with what was saved. */
int tcs_sched_clamp_attr(pthread_attr_t *attr, struct sched_param *saved, int *saved_policy) TCS_HIDDEN;
void tcs_sched_restore_attr(pthread_attr_t *attr, const struct sched_param *saved, int saved_policy) TCS_HIDDEN;

#endif
