/* The controller's journal (journal_write.c; the layout is tcs/journal.h):
 * recording, what the program read and asked is appended; replaying, it is
 * taken from the record instead (replay.h), until the program departs from
 * it. What is here never waits: the round trips and waits below which
 * replaying stands note into it. */
#ifndef TCS_PRELOAD_JOURNAL_WRITE_H
#define TCS_PRELOAD_JOURNAL_WRITE_H

#include "runtime.h"
#include "tcs/journal.h"

/* Maps the journal the clock page announces (start-up). */
int tcs_start_journal(void) TCS_HIDDEN;
/* Recording: appends an entry (nothing when not recording). */
void tcs_journal_note(unsigned kind, unsigned type, int64_t value, int64_t arg) TCS_HIDDEN;
/* How many entries the mapping holds. */
uint64_t tcs_journal_entries_max(void) TCS_HIDDEN;
/* Requests made between these are tcs's own, not the program's: none is
 * journalled, and no entry of a record is taken for them. */
void tcs_replay_inner_begin(void) TCS_HIDDEN;
void tcs_replay_inner_end(void) TCS_HIDDEN;
/* How many such requests this thread is inside (0: the program's). */
int tcs_replay_inner_depth(void) TCS_HIDDEN;
/* Replaying, and not departed. */
int tcs_replaying(void) TCS_HIDDEN;
/* A new child: the journal was its parent's. */
void tcs_journal_forget(void) TCS_HIDDEN;
/* Recording: the request of this type, whose charge point the program's
 * time v had reached, is journalled when its WAKE says at what time it was
 * charged (tcs_journal_answered, called for every answer). */
void tcs_journal_pending(unsigned type, int64_t v) TCS_HIDDEN;
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
