/* The controller's journal (journal_write.h): appended to while recording; the
 * cursor and the departure replaying are replay.c's, which waits where
 * this file never does. Runs in any context, signal handlers included: no
 * locks; a slot is claimed with one compare-and-swap. */
#include <sys/mman.h>

#include "journal_write.h"
#include "raw_syscall.h"
#include "report.h"

/* Entries the mapping holds (from its size, not from what the page says). */
static uint64_t tcs_journal_capacity;
/* Threads numbered as they first journal: the first is 0. */
static uint32_t tcs_journal_threads;
static __thread uint32_t tcs_journal_thread; /* its number + 1 (0: none yet) */
/* Recording: how far the ring's head may go, as this thread last read the
 * coordinator's tail (plus the capacity). The tail is on a line the
 * coordinator writes at every drain, a few times a cycle: read once a lap
 * instead of at every append, or when the ring looks full. */
static __thread uint64_t tcs_journal_room_end;
/* Recording: the request whose charge point was taken, journalled when its
 * WAKE says at what time it was charged; and the time the program had
 * reached then. */
static __thread unsigned tcs_pending_request;
static __thread int64_t tcs_pending_request_v;
/* A wait of tcs's own is under way (reaching the record's time, or asking
 * the world's after the coordinator stepped it aside), whose charge point
 * is no request of the program's: neither journalled nor replayed. */
static __thread int tcs_replay_inner;

int tcs_start_journal(void)
{
	uint64_t bytes = tcs_rt.page->journal_bytes;
	tcs_rt.journal = NULL;
	if (bytes == 0)
		return 0;
	if (bytes < TCS_JOURNAL_HEADER || bytes > (1ull << 34)) {
		tcs_say("the clock page's journal size is not valid", "; refusing to run in real time", NULL);
		tcs_sys1(SYS_exit_group, 2);
	}
	long m = tcs_sys6(SYS_mmap, NULL, (long)bytes, PROT_READ | PROT_WRITE, MAP_SHARED, tcs_rt.page_fd,
			  TCS_JOURNAL_OFFSET);
	if (m < 0 && m > -4096) {
		tcs_say("cannot map the journal (--record, --replay)", "; refusing to run in real time", NULL);
		tcs_sys1(SYS_exit_group, 2);
	}
	struct tcs_journal *j = (struct tcs_journal *)m;
	if (j->magic != TCS_JOURNAL_MAGIC) {
		tcs_say("the journal does not match the coordinator (mixed installations?)",
			"; refusing to run in real time", NULL);
		tcs_sys1(SYS_exit_group, 2);
	}
	tcs_journal_capacity = (bytes - TCS_JOURNAL_HEADER) / sizeof(struct tcs_journal_entry);
	tcs_rt.journal = j;
	return 0;
}

void tcs_journal_forget(void)
{
	if (tcs_rt.journal)
		tcs_sys2(SYS_munmap, tcs_rt.journal, (long)tcs_rt.page->journal_bytes);
	tcs_rt.journal = NULL;
}

static uint32_t tcs_thread_number(void)
{
	if (!tcs_journal_thread)
		tcs_journal_thread = __atomic_add_fetch(&tcs_journal_threads, 1, __ATOMIC_RELAXED);
	return tcs_journal_thread - 1;
}

int tcs_replaying(void)
{
	const struct tcs_journal *j = tcs_rt.journal;
	return j && j->replaying && !__atomic_load_n(&j->departed, __ATOMIC_ACQUIRE);
}

uint64_t tcs_journal_entries_max(void)
{
	return tcs_journal_capacity;
}

void tcs_journal_note(unsigned kind, unsigned type, int64_t value, int64_t arg)
{
	struct tcs_journal *j = tcs_rt.journal;
	if (!j || j->replaying || tcs_journal_capacity == 0)
		return;
	uint64_t h = __atomic_load_n(&j->head, __ATOMIC_RELAXED);
	do {
		if (h >= tcs_journal_room_end) {
			tcs_journal_room_end = __atomic_load_n(&j->tail, __ATOMIC_ACQUIRE) + tcs_journal_capacity;
			if (h >= tcs_journal_room_end) {
				__atomic_add_fetch(&j->lost, 1, __ATOMIC_RELAXED);
				return;
			}
		}
	} while (!__atomic_compare_exchange_n(&j->head, &h, h + 1, 1, __ATOMIC_ACQ_REL, __ATOMIC_RELAXED));
	struct tcs_journal_entry *e = &tcs_journal_entries(j)[h % tcs_journal_capacity];
	e->value = value;
	e->arg = arg;
	e->type = (uint16_t)type;
	e->thread = tcs_thread_number();
	__atomic_store_n(&e->kind, (uint16_t)kind, __ATOMIC_RELEASE); /* filled: the coordinator may take it */
}

void tcs_replay_inner_begin(void)
{
	tcs_replay_inner++;
}

void tcs_replay_inner_end(void)
{
	tcs_replay_inner--;
}

int tcs_replay_inner_depth(void)
{
	return tcs_replay_inner;
}

void tcs_journal_pending(unsigned type, int64_t v)
{
	tcs_pending_request = type;
	tcs_pending_request_v = v;
}

void tcs_journal_answered(unsigned type, int64_t v)
{
	if (!tcs_pending_request || tcs_pending_request != type)
		return;
	tcs_pending_request = 0;
	/* Never before what the program had seen: a request the coordinator
	 * found its controller not running for (two controllers starting, seen)
	 * is charged at its last slice's end, and the program's clock reads
	 * since were later. */
	tcs_journal_note(TCS_J_CHARGE, type, v > tcs_pending_request_v ? v : tcs_pending_request_v, 0);
}
