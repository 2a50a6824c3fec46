/* Parking a thread in virtual time on an object another thread signals
 * (parking.c). */
#ifndef TCS_PARKING_H
#define TCS_PARKING_H

#include "runtime.h"
#include "wait.h"

/* Threads parked now: zero makes every waker's check one load. */
extern int tcs_parked_count TCS_HIDDEN;

/* Registers this thread as parked on addr: a slot, or -errno (it may wait
 * anyway: it then re-checks at every step). */
int tcs_park_begin(const void *addr) TCS_HIDDEN;
/* Waits (t as for tcs_wait); a tcs_wait result: TCS_WAIT_FD when woken. */
int tcs_park_wait(int slot, struct tcs_wait_time *t, unsigned flags) TCS_HIDDEN;
void tcs_park_end(int slot) TCS_HIDDEN;
/* Wakes every thread parked on addr; how many. */
int tcs_unpark_all(const void *addr) TCS_HIDDEN;

static inline int tcs_unpark(const void *addr)
{
	return __atomic_load_n(&tcs_parked_count, __ATOMIC_RELAXED) ? tcs_unpark_all(addr) : 0;
}

#endif
