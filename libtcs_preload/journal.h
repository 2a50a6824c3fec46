/* The controller's journal (journal.c; the layout is tcs/journal.h):
 * recording, what the program read and asked is appended; replaying, it is
 * taken from the record instead, until the program departs from it. */
#ifndef TCS_PRELOAD_JOURNAL_H
#define TCS_PRELOAD_JOURNAL_H

#include "runtime.h"
#include "tcs/journal.h"

/* Maps the journal the clock page announces (start-up). */
int tcs_start_journal(void) TCS_HIDDEN;

/* Recording: appends an entry (nothing when not recording). */
void tcs_journal_note(unsigned kind, unsigned type, int64_t value, int64_t arg) TCS_HIDDEN;

/* Replaying, and not departed: *out is the record's next entry, which must
 * be of this kind (and, for TCS_J_CHARGE, type), and not before the time
 * reached already: returns 1. Anything else: 0, and the first such call is
 * the departure, told to the coordinator in the journal. */
int tcs_replay_take(unsigned kind, unsigned type, struct tcs_journal_entry *out) TCS_HIDDEN;
/* Replaying: virtual time v is reached, by a wait of the replay's own where
 * the world must step first (tcs_spin_to); not from inside a hook. */
void tcs_replay_reach(int64_t v) TCS_HIDDEN;
/* Requests made between these are tcs's own, not the program's: none is
 * journalled, and no entry of a record is taken for them. */
void tcs_replay_inner_begin(void) TCS_HIDDEN;
void tcs_replay_inner_end(void) TCS_HIDDEN;

/* Replaying, and not departed. */
int tcs_replaying(void) TCS_HIDDEN;
/* Replaying, and not departed: whether the record's next entry is of this
 * kind and type (it stays there). */
int tcs_replay_next(unsigned kind, unsigned type) TCS_HIDDEN;
/* Replaying: the call just taken from the record came out otherwise (value:
 * what it came to): the departure. */
void tcs_replay_depart(unsigned kind, int64_t value) TCS_HIDDEN;

/* Replaying: a clock's value from the record (1), its time reached. */
int tcs_replay_clock(unsigned kind, int64_t *value) TCS_HIDDEN;

/* A new child: the journal was its parent's. */
void tcs_journal_forget(void) TCS_HIDDEN;

/* A request's charge point (vclock.c): replaying, its time from the record
 * (and the record's time is reached); recording, the WAKE's word on its
 * time is journalled as it comes (tcs_journal_answered). */
void tcs_journal_request(unsigned type) TCS_HIDDEN;
void tcs_journal_answered(unsigned type, int64_t v) TCS_HIDDEN;

static inline int tcs_journal_on(void)
{
	return tcs_rt.journal != NULL;
}

/* A journal to replay (departed from or not): a recording clock read need
 * not ask tcs_replay_clock, a call that says no. */
static inline int tcs_journal_replaying(void)
{
	return tcs_rt.journal != NULL && tcs_rt.journal->replaying;
}

#endif
