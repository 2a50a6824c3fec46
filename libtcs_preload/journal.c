/* The controller's journal (journal.h): appended to while recording, taken
 * from while replaying. Runs in any context, signal handlers included: no
 * locks; a slot is claimed with one compare-and-swap. */
#include <sys/mman.h>

#include "journal.h"
#include "raw_syscall.h"
#include "report.h"
#include "spin.h"
#include "wait.h"

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

static int tcs_replaying_from(const struct tcs_journal *j)
{
	return j && j->replaying && !__atomic_load_n(&j->departed, __ATOMIC_ACQUIRE);
}

int tcs_replaying(void)
{
	return tcs_replaying_from(tcs_rt.journal);
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

/* The first call the record does not have: said once, in the journal. */
static void tcs_depart(struct tcs_journal *j, unsigned kind, unsigned type, int64_t value,
		       const struct tcs_journal_entry *expected)
{
	struct tcs_journal_departure d = { 0 };
	d.v = tcs_vnow();
	d.kind = (uint16_t)kind;
	d.type = (uint16_t)type;
	d.value = value;
	if (expected) {
		d.expected_kind = expected->kind;
		d.expected_type = expected->type;
		d.expected_value = expected->value;
	}
	j->departure = d;
	__atomic_store_n(&j->departed, 1, __ATOMIC_RELEASE);
}

/* Virtual time v reached computing, as in the recorded run (where the
 * coordinator's stops, in the record, come first). held: inside a hook's
 * wait, before its request. */
static void tcs_replay_to(int64_t v, int held)
{
	tcs_replay_inner++;
	(void)tcs_spin_to(v, held);
	tcs_replay_inner--;
}

/* The record's stop at v: the world steps there, as it did there. */
static void tcs_replay_stop(int64_t v, int held)
{
	if (v <= tcs_vnow() || (!held && !tcs_wait_enter()))
		return;
	tcs_replay_inner++;
	struct tcs_wait_time t = { v, 0, 0, 0, 0, 0 };
	(void)tcs_wait(&t, TCS_BLOCK_SPIN, 0, NULL, 0, NULL);
	tcs_replay_inner--;
	if (!held)
		tcs_wait_leave();
}

/* Replaying: the cursor in *at, the end of the table in *n (within the
 * mapping, whatever the coordinator wrote). */
static void tcs_replay_bounds(const struct tcs_journal *j, uint64_t *at, uint64_t *n)
{
	*at = __atomic_load_n(&j->head, __ATOMIC_RELAXED);
	*n = __atomic_load_n(&j->tail, __ATOMIC_RELAXED);
	if (*n > tcs_journal_capacity)
		*n = tcs_journal_capacity;
}

int tcs_replay_take(unsigned kind, unsigned type, struct tcs_journal_entry *out)
{
	struct tcs_journal *j = tcs_rt.journal;
	if (!tcs_replaying_from(j))
		return 0;
	uint64_t at, n;
	tcs_replay_bounds(j, &at, &n);
	/* The coordinator's stops before it, each where it was: a request's
	 * hook may wait for them (held), any other call outside a hook. */
	int held = kind == TCS_J_CHARGE;
	while (at < n && tcs_journal_entries(j)[at].kind == TCS_J_STOP) {
		int64_t v = tcs_journal_entries(j)[at].value;
		__atomic_store_n(&j->head, ++at, __ATOMIC_RELAXED);
		if (!tcs_replay_inner && (held || !tcs_in_wait))
			tcs_replay_stop(v, held);
	}
	if (at >= n) {
		tcs_depart(j, kind, type, 0, NULL);
		return 0;
	}
	struct tcs_journal_entry e = tcs_journal_entries(j)[at];
	if (e.kind != kind || (kind == TCS_J_CHARGE && e.type != type)) {
		tcs_depart(j, kind, type, 0, &e);
		return 0;
	}
	/* Virtual time never goes back: a request the record has earlier than
	 * now is one whose wait ended later here than there. */
	if ((kind == TCS_J_CLOCK || kind == TCS_J_CHARGE || kind == TCS_J_READ) && e.value < tcs_vnow()) {
		tcs_depart(j, kind, type, tcs_vnow(), &e);
		return 0;
	}
	__atomic_store_n(&j->head, at + 1, __ATOMIC_RELAXED);
	*out = e;
	return 1;
}

int tcs_replay_next(unsigned kind, unsigned type)
{
	struct tcs_journal *j = tcs_rt.journal;
	if (!tcs_replaying_from(j))
		return 0;
	uint64_t at, n;
	tcs_replay_bounds(j, &at, &n);
	while (at < n && tcs_journal_entries(j)[at].kind == TCS_J_STOP)
		at++; /* (the coordinator's, taken as the next entry is) */
	if (at >= n)
		return 0;
	const struct tcs_journal_entry *e = &tcs_journal_entries(j)[at];
	return e->kind == kind && e->type == type;
}

void tcs_replay_depart(unsigned kind, int64_t value)
{
	struct tcs_journal *j = tcs_rt.journal;
	if (!tcs_replaying_from(j))
		return;
	uint64_t at = __atomic_load_n(&j->head, __ATOMIC_RELAXED);
	struct tcs_journal_entry e = { 0 };
	if (at > 0 && at - 1 < tcs_journal_capacity)
		e = tcs_journal_entries(j)[at - 1];
	tcs_depart(j, kind, 0, value, &e);
}

void tcs_replay_reach(int64_t v)
{
	/* A handler's call inside a hook cannot ask: the hook's own request
	 * reaches its time. */
	if (!tcs_in_wait && !tcs_replay_inner)
		tcs_replay_to(v, 0);
}

void tcs_replay_inner_begin(void)
{
	tcs_replay_inner++;
}

void tcs_replay_inner_end(void)
{
	tcs_replay_inner--;
}

int tcs_replay_clock(unsigned kind, int64_t *value)
{
	struct tcs_journal_entry e;
	if (!tcs_replay_take(kind, 0, &e))
		return 0;
	*value = e.value;
	if (kind == TCS_J_CLOCK)
		tcs_replay_reach(e.value);
	return 1;
}

void tcs_journal_request(unsigned type)
{
	struct tcs_journal *j = tcs_rt.journal;
	if (!j || type == TCS_MSG_EARLY || tcs_replay_inner)
		return;
	if (!j->replaying) {
		tcs_pending_request = type;
		tcs_pending_request_v = tcs_vnow();
		return;
	}
	struct tcs_journal_entry e;
	if (!tcs_replay_take(TCS_J_CHARGE, type, &e))
		return;
	tcs_replay_to(e.value, 1); /* inside the request's hook, before it is sent */
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
