/* The idioms program: the calls on interval timers, POSIX timers, timerfds and waits for a signal (calls_timers.c). */
#ifndef TCS_IDIOMS_CALLS_TIMERS_H
#define TCS_IDIOMS_CALLS_TIMERS_H

#include "idioms.h"

extern const struct itimerval driver_spec;
void c_alarm(struct ctx *c);
void c_setitimer(struct ctx *c);
void c_getitimer(struct ctx *c);
void c_timer_create(struct ctx *c);
void c_timer_settime(struct ctx *c);
void c_timer_gettime(struct ctx *c);
void c_timer_getoverrun(struct ctx *c);
void c_timerfd(struct ctx *c);
void c_timerfd_gettime(struct ctx *c);
void c_timerfd_read(struct ctx *c);
void c_sigsuspend(struct ctx *c);
void c_pause(struct ctx *c);

#endif
