/* Parking: how a thread waits in virtual time for another thread of its
 * process (a condition variable, semaphore, mutex or futex). It registers
 * the object's address with a sequence number reserved for its wait, then
 * waits on its own channel; whoever signals the object (the hooks of
 * pthread_cond_signal, sem_post, pthread_mutex_unlock, FUTEX_WAKE) sends
 * EARLY with that number on the parked thread's channel, and the
 * coordinator ends the wait. Registering before the last check of the
 * object (and an EARLY that may arrive before the BLOCK) means no wake-up
 * is lost. Waking every thread parked on an address is a spurious wake-up
 * to those that were not meant, which all these primitives allow. */
#include <sys/socket.h>

#include "parking.h"
#include "raw_syscall.h"
#include "report.h"
#include "spin_lock.h"
#include "thread_channels.h"
#include "timer_slack.h"
#include "vclock.h"

#define TCS_MAX_PARKED 256

struct tcs_parked {
	const void *addr;
	int fd;
	uint32_t seq;
	int poked;
	int used;
};

static struct tcs_parked tcs_parked_slots[TCS_MAX_PARKED];
int tcs_parked_count;

int tcs_park_begin(const void *addr)
{
	int fd = tcs_my_channel();
	if (fd < 0)
		return fd;
	int slot = -ENOSPC;
	uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_PARKED]);
	for (int i = 0; i < TCS_MAX_PARKED; i++) {
		struct tcs_parked *p = &tcs_parked_slots[i];
		if (p->used)
			continue;
		p->addr = addr;
		p->fd = fd;
		p->seq = __atomic_add_fetch(&tcs_rt.next_seq, 1, __ATOMIC_RELAXED);
		p->poked = 0;
		p->used = 1;
		__atomic_add_fetch(&tcs_parked_count, 1, __ATOMIC_RELAXED);
		slot = i;
		break;
	}
	tcs_unlock(&tcs_locks[TCS_LOCK_PARKED], signals);
	if (slot == -ENOSPC) {
		static int once;
		tcs_report_once(&once, "more than 256 threads wait at once; the others re-check every step");
	}
	return slot;
}

int tcs_park_wait(int slot, struct tcs_wait_time *t, unsigned flags)
{
	if (slot >= 0)
		t->seq = tcs_parked_slots[slot].seq;
	else
		flags |= TCS_BLOCK_RECHECK; /* no slot: nobody can poke it */
	t->slack = tcs_timer_slack();
	return tcs_wait(t, TCS_BLOCK_SYNC, flags, NULL, 0, NULL);
}

void tcs_park_end(int slot)
{
	if (slot < 0)
		return;
	uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_PARKED]);
	tcs_parked_slots[slot].used = 0;
	tcs_parked_slots[slot].addr = NULL;
	__atomic_sub_fetch(&tcs_parked_count, 1, __ATOMIC_RELAXED);
	tcs_unlock(&tcs_locks[TCS_LOCK_PARKED], signals);
}

int tcs_unpark_all(const void *addr)
{
	int fds[TCS_MAX_PARKED];
	uint32_t seqs[TCS_MAX_PARKED];
	int n = 0;
	uint64_t signals = tcs_lock(&tcs_locks[TCS_LOCK_PARKED]);
	for (int i = 0; i < TCS_MAX_PARKED; i++) {
		struct tcs_parked *p = &tcs_parked_slots[i];
		if (!p->used || p->addr != addr || p->poked)
			continue;
		p->poked = 1;
		fds[n] = p->fd;
		seqs[n++] = p->seq;
	}
	tcs_unlock(&tcs_locks[TCS_LOCK_PARKED], signals);
	/* Where this thread's process is: the coordinator's own reading of a
	 * running process's CPU lags by up to a kernel tick. */
	int64_t cpu = n > 0 ? tcs_charge_point(TCS_MSG_EARLY) : 0;
	for (int i = 0; i < n; i++) {
		struct tcs_msg m = tcs_msg_make(TCS_MSG_EARLY, seqs[i]);
		m.kind = TCS_EARLY_FD;
		m.cpu = cpu;
		long r;
		do
			r = tcs_sys6(SYS_sendto, fds[i], (long)&m, sizeof m, MSG_NOSIGNAL, 0, 0);
		while (r == -EINTR);
	}
	return n;
}
