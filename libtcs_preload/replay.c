/* Replaying a journal (replay.h): the record's next entry taken for each
 * call the program makes, the record's times reached by waits of tcs's own
 * (tcs_spin_to, tcs_wait), the first call that comes out otherwise told as
 * the departure. Above the waits it makes; the journal itself (journal_write.c)
 * is below them. */
#include "replay.h"

#include "spin.h"
#include "wait.h"

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
	tcs_replay_inner_begin();
	(void)tcs_spin_to(v, held);
	tcs_replay_inner_end();
}

/* The record's stop at v: the world steps there, as it did there. */
static void tcs_replay_stop(int64_t v, int held)
{
	if (v <= tcs_vnow() || (!held && !tcs_wait_enter()))
		return;
	tcs_replay_inner_begin();
	struct tcs_wait_time t = { v, 0, 0, 0, 0, 0 };
	(void)tcs_wait(&t, TCS_BLOCK_SPIN, 0, NULL, 0, NULL);
	tcs_replay_inner_end();
	if (!held)
		tcs_wait_leave();
}

/* Replaying: the cursor in *at, the end of the table in *n (within the
 * mapping, whatever the coordinator wrote). */
static void tcs_replay_bounds(const struct tcs_journal *j, uint64_t *at, uint64_t *n)
{
	*at = __atomic_load_n(&j->head, __ATOMIC_RELAXED);
	*n = __atomic_load_n(&j->tail, __ATOMIC_RELAXED);
	if (*n > tcs_journal_entries_max())
		*n = tcs_journal_entries_max();
}

int tcs_replay_take(unsigned kind, unsigned type, struct tcs_journal_entry *out)
{
	struct tcs_journal *j = tcs_rt.journal;
	if (!tcs_replaying())
		return 0;
	uint64_t at, n;
	tcs_replay_bounds(j, &at, &n);
	/* The coordinator's stops before it, each where it was: a request's
	 * hook may wait for them (held), any other call outside a hook. */
	int held = kind == TCS_J_CHARGE;
	while (at < n && tcs_journal_entries(j)[at].kind == TCS_J_STOP) {
		int64_t v = tcs_journal_entries(j)[at].value;
		__atomic_store_n(&j->head, ++at, __ATOMIC_RELAXED);
		if (!tcs_replay_inner_depth() && (held || !tcs_in_wait))
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
	if (!tcs_replaying())
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
	if (!tcs_replaying())
		return;
	uint64_t at = __atomic_load_n(&j->head, __ATOMIC_RELAXED);
	struct tcs_journal_entry e = { 0 };
	if (at > 0 && at - 1 < tcs_journal_entries_max())
		e = tcs_journal_entries(j)[at - 1];
	tcs_depart(j, kind, 0, value, &e);
}

void tcs_replay_reach(int64_t v)
{
	/* A handler's call inside a hook cannot ask: the hook's own request
	 * reaches its time. */
	if (!tcs_in_wait && !tcs_replay_inner_depth())
		tcs_replay_to(v, 0);
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

void tcs_replay_request(unsigned type)
{
	struct tcs_journal *j = tcs_rt.journal;
	if (!j || type == TCS_MSG_EARLY || tcs_replay_inner_depth())
		return;
	if (!j->replaying) {
		tcs_journal_pending(type, tcs_vnow());
		return;
	}
	struct tcs_journal_entry e;
	if (!tcs_replay_take(TCS_J_CHARGE, type, &e))
		return;
	tcs_replay_to(e.value, 1); /* inside the request's hook, before it is sent */
}

