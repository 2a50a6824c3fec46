/* Replaying the controller's journal (replay.c): each call the program
 * makes takes the record's next entry, and the record's times are reached
 * with waits of tcs's own. */
#ifndef TCS_PRELOAD_REPLAY_H
#define TCS_PRELOAD_REPLAY_H

#include "journal_write.h"
#include "runtime.h"

/* Replaying, and not departed: *out is the record's next entry, which must
 * be of this kind (and, for TCS_J_CHARGE, type), and not before the time
 * reached already: returns 1. Anything else: 0, and the first such call is
 * the departure, told to the coordinator in the journal. */
int tcs_replay_take(unsigned kind, unsigned type, struct tcs_journal_entry *out) TCS_HIDDEN;
/* Replaying: virtual time v is reached, by a wait of the replay's own where
 * the world must step first (tcs_spin_to); not from inside a hook. */
void tcs_replay_reach(int64_t v) TCS_HIDDEN;
/* Replaying, and not departed: whether the record's next entry is of this
 * kind and type (it stays there). */
int tcs_replay_next(unsigned kind, unsigned type) TCS_HIDDEN;
/* Replaying: the call just taken from the record came out otherwise (value:
 * what it came to): the departure. */
void tcs_replay_depart(unsigned kind, int64_t value) TCS_HIDDEN;
/* Replaying: a clock's value from the record (1), its time reached. */
int tcs_replay_clock(unsigned kind, int64_t *value) TCS_HIDDEN;
/* A request's charge point, with a journal (vclock.c calls it through the
 * pointer start-up sets): replaying, its time from the record (and the
 * record's time is reached); recording, the request is pending until its
 * WAKE says at what time it was charged. */
void tcs_replay_request(unsigned type) TCS_HIDDEN;

#endif
