/* The idioms program: the calls on clocks, sleeps and multiplexers (calls_time.c). */
#ifndef TCS_IDIOMS_CALLS_TIME_H
#define TCS_IDIOMS_CALLS_TIME_H

#include "idioms.h"

void c_clock_mono(struct ctx *c);
void c_clock_real(struct ctx *c);
void c_clock_process(struct ctx *c);
void c_clock_thread(struct ctx *c);
void c_gettimeofday(struct ctx *c);
void c_time(struct ctx *c);
void c_timespec_get(struct ctx *c);
void c_clock(struct ctx *c);
void c_times(struct ctx *c);
void c_getrusage(struct ctx *c);
void c_nanosleep(struct ctx *c);
void c_clock_nanosleep(struct ctx *c);
void c_clock_nanosleep_abs(struct ctx *c);
void c_usleep(struct ctx *c);
void c_sleep(struct ctx *c);
void c_thrd_sleep(struct ctx *c);
void c_select(struct ctx *c);
void c_pselect(struct ctx *c);
void c_poll(struct ctx *c);
void c_ppoll(struct ctx *c);
void c_epoll_wait(struct ctx *c);
void c_epoll_pwait(struct ctx *c);

#endif
