// Journals (record_replay.h). Everything in a journal was written by the
// controller: each entry is read once, its kind checked, and the ring's
// positions are bounded by what the coordinator itself has taken.
#include "record_replay.h"

#include <algorithm>
#include <cinttypes>
#include <cstdio>

#include "record.h"
#include "slices.h"
#include "waits.h"
#include "transitions.h"
#include "world_steps.h"

namespace tcs {

namespace {
// Entries a record message holds at most (smaller: at a controller's end).
constexpr size_t kBatch = 4096;
} // namespace

void journal_stop(Run &run, Controller &c, int64_t overshoot)
{
	tcs_journal *j = c.journal();
	if (!j || j->replaying)
		return;
	drain_journal(run, c);
	tcs_journal_entry stop = {};
	stop.kind = TCS_J_STOP;
	stop.value = c.v();
	stop.arg = overshoot;
	c.journal_batch.push_back(stop);
}

// An entry drained, in its place: a call's time is never after a stop that
// came later, so one whose time is before stops already in the batch was
// made before them, and journalled after (a request answered at once is
// journalled as its answer comes, and the stop may fall in between; or the
// stop fell in the middle of its append).
static void keep_in_order(std::vector<tcs_journal_entry> &batch, const tcs_journal_entry &e)
{
	size_t at = batch.size();
	if (e.kind == TCS_J_CLOCK || e.kind == TCS_J_CHARGE || e.kind == TCS_J_READ)
		while (at > 0 && batch[at - 1].kind == TCS_J_STOP && batch[at - 1].value > e.value)
			at--;
	if (at == batch.size())
		batch.push_back(e); // (nearly always: entries come in order)
	else
		batch.insert(batch.begin() + (long)at, e);
}

void drain_journal(Run &run, Controller &c, bool flush)
{
	tcs_journal *j = c.journal();
	if (!j || j->replaying)
		return;
	const uint64_t cap = c.journal_capacity();
	uint64_t tail = c.journal_tail;
	uint64_t head = __atomic_load_n(&j->head, __ATOMIC_ACQUIRE);
	if (head - tail > cap)
		head = tail + cap; // (a controller's word)
	tcs_journal_entry *ring = tcs_journal_entries(j);
	// The slot's index kept as it goes round (not a division an entry).
	for (uint64_t slot = tail % cap; tail != head; tail++, slot = slot + 1 == cap ? 0 : slot + 1) {
		tcs_journal_entry *e = &ring[slot];
		uint16_t kind = __atomic_load_n(&e->kind, __ATOMIC_ACQUIRE);
		if (kind == 0)
			break; // claimed, not yet filled: next time
		tcs_journal_entry copy = *e;
		copy.kind = kind;
		__atomic_store_n(&e->kind, (uint16_t)0, __ATOMIC_RELAXED);
		if (kind < TCS_J_STOP)
			keep_in_order(c.journal_batch, copy);
	}
	c.journal_tail = tail;
	__atomic_store_n(&j->tail, tail, __ATOMIC_RELEASE);
	if (!c.journal_lost && __atomic_load_n(&j->lost, __ATOMIC_RELAXED) != 0) {
		c.journal_lost = true; // (said once)
		warn_once(run, "record: '" + c.name + "' read its clocks more often between two stops than its journal holds; "
			  "the record is incomplete from " + std::to_string(c.v() / 1e9) + " s, where a replay departs");
	}
	// (Not with a stop last: what it drains next may go before it.)
	bool full = c.journal_batch.size() >= kBatch && c.journal_batch.back().kind != TCS_J_STOP;
	if (full || (flush && !c.journal_batch.empty())) {
		run.trace.journal(c.id, c.journal_batch);
		c.journal_batch.clear(); // (its room kept for the next batch)
	}
}

static std::string what_of(unsigned kind, unsigned type)
{
	static const char *const types[] = { "", "HELLO", "wait", "EARLY", "WAKE", "device open", "device sync",
					     "timer", "fork", "THREAD", "signal" };
	std::string s = tcs_journal_kind_name(kind);
	if (kind == TCS_J_CHARGE && type < sizeof types / sizeof *types && *types[type])
		s = std::string(types[type]) + " " + s;
	return s;
}

// From here on, the run measures again: cpu mode, with every controller's
// own CPU (the record's charges end here).
static void go_live(Run &run)
{
	if (!run.replaying)
		return;
	run.replaying = false;
	run.cfg.mode = TCS_MODE_CPU;
	for (auto &c : run.ctls) {
		c->set_page_mode(TCS_MODE_CPU);
		c->set_page_flag(TCS_PAGE_REPLAY, false);
	}
}

static void say_departure(Run &run, Controller &c, const std::string &what, bool ended = false)
{
	c.departed = true;
	if (run.ending) {
		// The run's end (its duration, a signal) is tcs's, not in the record:
		// what the program does from there on is no departure of its own.
		go_live(run);
		return;
	}
	warn_once(run, "replay: '" + c.name + "' departs from the record " + what +
			       (ended ? "" : "; the run goes on live from there"));
	go_live(run);
}

bool replay_stop(Run &run, Controller &c, const ::tcs_msg &m, int fd, pid_t tid)
{
	if (!run.replaying || m.kind != TCS_BLOCK_SPIN || c.state() != CtlState::Running || c.multithreaded())
		return false;
	run.lanes.leave(c);
	int64_t cpu = charge_point(run, c, m.cpu);
	c.account(cpu, run.cfg.mode);
	// Where the record's stop was: no further than the world's next step
	// or its next timer (the controller's word, held to that).
	int64_t at = std::clamp(m.deadline, c.v(), std::max(c.v(), c.spin_limit()));
	c.charged += at - c.v();
	advance(c, at);
	c.stats.preemptions++;
	// The preload took the record's stop it waits for: the one before its
	// cursor (its word, checked against the stop it asked for).
	tcs_journal *j = c.journal();
	uint64_t taken = __atomic_load_n(&j->head, __ATOMIC_RELAXED) - 1;
	int64_t overshoot = 0;
	if (taken < std::min<uint64_t>(j->tail, c.journal_capacity())) {
		const tcs_journal_entry &e = tcs_journal_entries(j)[taken];
		if (e.kind == TCS_J_STOP && e.value == at)
			overshoot = e.arg;
	}
	trace_slice_end(run, c, "preempted", cpu, -1, overshoot);
	c.cpu_at_end = cpu;
	c.wait.seq = m.seq;
	c.wait.fd = fd;
	c.wait.tid = tid;
	c.wait.active = false; // (no wait of the program's)
	move(run, c, CtlMove::Preempt);
	wake(run, c, at, TCS_WAKE_DEADLINE);
	schedule(run);
	return true;
}

// Replaying: where c's journal goes on past the coordinator's own entries
// up to kind `upto` (stops; and the exit, with TCS_J_EXIT), and in *n where
// it ends (both within the table, whatever the controller wrote).
static uint64_t next_of_program(Controller &c, unsigned upto, uint64_t *n)
{
	tcs_journal *j = c.journal();
	const tcs_journal_entry *e = tcs_journal_entries(j);
	*n = std::min<uint64_t>(j->tail, c.journal_capacity());
	uint64_t at = __atomic_load_n(&j->head, __ATOMIC_RELAXED);
	while (at < *n && e[at].kind >= TCS_J_STOP && e[at].kind <= upto)
		at++;
	return std::min(at, *n);
}

void replay_exit(Run &run, Controller &c)
{
	tcs_journal *j = c.journal();
	if (!run.replaying || !j || !j->replaying || c.departed)
		return;
	uint64_t n, at = next_of_program(c, TCS_J_STOP, &n);
	if (at >= n)
		return;
	const tcs_journal_entry e = tcs_journal_entries(j)[at];
	if (e.kind != TCS_J_EXIT || e.value <= c.v())
		return;
	c.charged += e.value - c.v();
	place_at(c, e.value);
}

static std::string values_text(const std::vector<double> *values)
{
	if (!values)
		return "a malformed record";
	std::string s;
	for (double v : *values) {
		char buf[32];
		snprintf(buf, sizeof buf, "%s%.9g", s.empty() ? "" : " ", v);
		s += buf;
	}
	return "'" + s + "'";
}

void replay_command(Run &run, Controller &c, const std::string &path, const std::vector<double> *values)
{
	if (!run.replaying || c.departed || !c.journal())
		return;
	auto all = run.cfg.replay->commands.find(c.id);
	size_t i = c.commands_replayed++;
	const RecordedCommand *r =
		all != run.cfg.replay->commands.end() && i < all->second.size() ? &all->second[i] : nullptr;
	if (r && r->path == path && r->v == c.v() && r->malformed == !values && (!values || r->values == *values))
		return;
	char at[64];
	snprintf(at, sizeof at, "at %.9f s: ", (double)c.v() / 1e9);
	std::string what = std::string(at) + "command " + values_text(values) + " to " + path;
	if (!r)
		what += " past the record's last command";
	else
		what += " where the record has " + values_text(r->malformed ? nullptr : &r->values) +
			(r->path != path ? " to " + r->path : "") +
			(r->v != c.v() ? " at " + std::to_string(r->v / 1e9) + " s" : "");
	say_departure(run, c, what);
}

void check_departure(Run &run, Controller &c)
{
	tcs_journal *j = c.journal();
	if (!j || !j->replaying || c.departed || !__atomic_load_n(&j->departed, __ATOMIC_ACQUIRE))
		return;
	tcs_journal_departure d = j->departure;
	char at[64];
	snprintf(at, sizeof at, "at %.9f s", (double)d.v / 1e9);
	std::string what = std::string(at) + ": " + what_of(d.kind, d.type);
	if (d.expected_kind == 0)
		what += " past the record's end";
	else if (d.expected_kind == d.kind && d.expected_type == d.type)
		what += " at " + std::to_string(d.value / 1e9) + " s, where the record has it at " +
			std::to_string(d.expected_value / 1e9) + " s";
	else
		what += " where the record has a " + what_of(d.expected_kind, d.expected_type);
	say_departure(run, c, what);
}

void journal_ends(Run &run, Controller &c)
{
	tcs_journal *j = c.journal();
	if (!j)
		return;
	if (!j->replaying) {
		drain_journal(run, c);
		tcs_journal_entry end = {};
		end.kind = TCS_J_EXIT;
		end.value = c.v();
		c.journal_batch.push_back(end);
		drain_journal(run, c, true);
		return;
	}
	check_departure(run, c);
	uint64_t n, at = next_of_program(c, TCS_J_EXIT, &n);
	if (!c.departed && !run.ending && at < n) {
		char what[96];
		snprintf(what, sizeof what, "at %.9f s: it ended with %" PRIu64 " of the record's entries not reached",
			 (double)c.v() / 1e9, n - at);
		say_departure(run, c, what, true);
	}
}

} // namespace tcs
