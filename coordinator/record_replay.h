// Recording and replaying (docs/DESIGN.md §2): controllers' journals drained
// into the record, and a replay's departures said and turned into a live
// run (tcs/journal.h has the journal itself, trace/record.h the record).
#pragma once

#include "run.h"

namespace tcs {

// Recording: what c journalled since the last time goes into the record
// (kept in batches; flush: now).
void drain_journal(Run &run, Controller &c, bool flush = false);
// Recording: c was preempted (its slice ends at c.v(), overshoot ns of real
// CPU past its budget): the stop goes into the record after what it
// journalled before.
void journal_stop(Run &run, Controller &c, int64_t overshoot);
// Replaying: if c has departed from the record, says where, once, and the
// run goes on live from there.
void check_departure(Run &run, Controller &c);
// Replaying: c's command (values; null: malformed) to path, taken: one the
// record does not have there is its departure.
void replay_command(Run &run, Controller &c, const std::string &path, const std::vector<double> *values);
// Replaying: a spin stop of c's (TCS_BLOCK_SPIN) that stands for one of the
// record's preemptions, taken as one (true): its slice ends at the stop's
// time, all of it charged, and it goes on once the world is there.
bool replay_stop(Run &run, Controller &c, const ::tcs_msg &m, int fd, pid_t tid);
// Replaying: c has ended; its last slice ends where the record's did.
void replay_exit(Run &run, Controller &c);
// c has ended: the rest of its journal recorded, or, replaying, whether it
// ended where the record does.
void journal_ends(Run &run, Controller &c);

} // namespace tcs
