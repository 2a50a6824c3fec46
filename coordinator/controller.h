// One controller process as the coordinator sees it: its channel, clock
// page and pidfd, where it stands in virtual time, and what it is doing.
// The scheduling decisions about it live in scheduler.cc.
#pragma once

#include <sys/types.h>

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "controller_state.h"
#include "error.h"
#include "device.h"
#include "mailbox_serve.h"
#include "realtime.h"
#include "spin_costs.h"
#include "tcs/clock_page.h"
#include "tcs/journal.h"
#include "tcs/protocol.h"
#include "unique_fd.h"

namespace tcs {

struct ControllerSpec {
	std::string path;              // resolved executable
	std::vector<std::string> argv; // as given
	double cpu_scale = 1.0;
	bool report_misses = false; // TCS_PAGE_REPORT_MISSES (set when tracing)
	// Started for someone else (coordinatord serving tcs-run --connect):
	// their environment, working directory and stdin/stdout/stderr. Empty,
	// empty and -1: the coordinator's own.
	std::optional<std::vector<std::string>> env;
	std::string cwd;
	std::array<int, 3> stdio = { -1, -1, -1 };
	// --seed: its key to the seeded randomness (tcs/random_stream.h); 0:
	// the system's, real.
	uint64_t random_key = 0;
	// --record: it journals every clock value it reads and the time of
	// every request; --replay: the record's journal for it, which it takes
	// them from (tcs/journal.h). Controllers tcs starts, not their children.
	bool record = false;
	const std::vector<tcs_journal_entry> *replay = nullptr;
};

// The constants every controller's clock page starts with.
struct ClockSetup {
	int64_t mono_ns = 0;
	int64_t real_ns = 0;
	int64_t tai_ns = 0;
	SpinCosts spin; // (lockstep's)
};

// A device request a controller waits on (TCS_MSG_DEV_SYNC): for the
// world to reach its step, or for a record of the sensor it reads.
struct DeviceSync {
	uint16_t kind = 0;   // TCS_SYNC_READ, TCS_SYNC_POLL
	int64_t handle = 0;  // the device (an index of Controller::devices)
	bool nonblock = false; // a read that returns -EAGAIN rather than wait
	int64_t deadline = TCS_NEVER; // a wire's read: it waits for data until then at most
};

// A signal timer of the controller (alarm, setitimer, timer_create): the
// coordinator sends signo at each expiry of its virtual time.
struct SignalTimer {
	int signo = 0;
	int tid = 0; // 0: the process
	int64_t next = TCS_NEVER;
	int64_t interval = 0;
};

// What the coordinator keeps of one channel of a controller: the main one,
// or a thread's (protocol.h, Threads).
struct ChannelState {
	int unanswered = 0;   // messages since the last WAKE sent on it
	uint32_t early_before_block = 0; // an EARLY whose BLOCK has not come yet
};

// A thread other than the main one: its own channel.
struct ThreadChannel {
	pid_t tid = 0;
	UniqueFd fd;
	ChannelState state;
};

// A request of one of the controller's threads that the coordinator holds
// unanswered: where its answer goes, what it asked, when it ends by itself,
// and once it is to end, why and with what result. A thread's wait beside
// the controller's own is one (Controller::side): another thread ran on
// when it began, or the controller waits in another thread's wait. It ends
// at its deadline (or a re-check, or an EARLY), when the controller is
// resumed there; the controller's virtual time passes only while no thread
// can run (scheduler.cc).
struct Request {
	int fd = -1;      // the channel it came on, and its answer goes on
	pid_t tid = 0;    // the thread that sent it
	uint32_t seq = 0;
	const char *kind = ""; // the trace's name for it (block_kind_name)
	uint16_t flags = 0;    // its TCS_BLOCK_* flags, as asked
	int64_t requested_at = 0; // the virtual time it was asked at (its WAKE says)
	int64_t asked = TCS_NEVER;    // the deadline asked for (deadline less its slack)
	int64_t deadline = TCS_NEVER; // when its timeout ends it
	int64_t rechecked_at = 0;     // the world's time at its last re-check
	uint16_t reason = 0; // TCS_WAKE_*: set when it is to end
	int64_t result = 0;  // what its WAKE carries (arg)
	bool absolute() const { return (flags & TCS_BLOCK_ABSOLUTE) != 0; } // a periodic loop's
};

// The trace's name for a wait of kind TCS_BLOCK_*.
inline const char *block_kind_name(uint16_t kind)
{
	return kind == TCS_BLOCK_SLEEP ? "sleep" : kind == TCS_BLOCK_POLL ? "poll" : kind == TCS_BLOCK_SPIN ? "spin" : "sync";
}

// The most timer slack a wait may ask for: its controller's to say, so
// bounded (Linux takes any; a second covers every use seen).
constexpr int64_t kMostSlack = TCS_NS_PER_S;

// When BLOCK m's wait ends by its timeout: at its deadline plus the timer
// slack its thread has (timer_slack.h), or exactly without slack.
inline int64_t timeout_end(const ::tcs_msg &m, bool slack)
{
	return slack ? tcs_ns_add(m.deadline, std::min(m.slack, kMostSlack)) : m.deadline;
}

// A thread's BLOCK m on channel fd, asked at virtual time v and last
// looked at when the world was at `now`; slack as timeout_end's.
inline Request request_of(const ::tcs_msg &m, int fd, pid_t tid, int64_t v, int64_t now, bool slack)
{
	Request w;
	w.fd = fd;
	w.tid = tid;
	w.seq = m.seq;
	w.deadline = timeout_end(m, slack);
	w.asked = m.deadline;
	w.flags = m.flags;
	w.kind = block_kind_name(m.kind);
	w.requested_at = v;
	w.rechecked_at = now;
	return w;
}

// The controller's own request being served (a BLOCK, or any request
// answered later: a device read's, a fork's) and, while it is Blocked, what
// ends its wait. A thread's wait beside it is a plain Request (own_wait()
// and transitions.h's own_wait_from() convert).
struct OwnWait : Request {
	OwnWait() { deadline = asked = 0, rechecked_at = -1, fd = -1; } // (fd -1: the main channel)
	bool active = false;      // a BLOCK is being served (for the trace)
	bool owed = false;        // its answer is to be sent (reason and result say what)
	int pass_fd = -1;         // an fd its answer passes (owned until sent)
	bool recheck = false;     // Blocked with per-step re-checks
	bool for_child = false;   // Blocked in wait/waitpid: a child's end wakes it
	bool devices = false;     // Blocked, and a record due on a sensor ends it
	int64_t signalled_at = TCS_NEVER; // signalled by another controller then
};

struct LoopStats {
	uint64_t waits = 0;          // BLOCK messages: the program's waits
	uint64_t spin_stops = 0;     // and the spins' (TCS_BLOCK_SPIN), not the program's
	void count_wait(const ::tcs_msg &m) { (m.kind == TCS_BLOCK_SPIN ? spin_stops : waits)++; }
	uint64_t absolute_waits = 0; // of which absolute deadlines (periodic loops)
	uint64_t preemptions = 0;    // budgets that ended with SIGSTOP
	uint64_t reported_misses = 0; // absolute waits sent though already past
};

struct Run;

class Controller {
public:
	static Result<std::unique_ptr<Controller>> start(int id, const ControllerSpec &spec, int mode,
							 const ClockSetup &clocks, const RealtimePlan &rt,
							 const std::string &preload,
							 const std::vector<BoundDevice> &devices);
	// A child of parent (fork, posix_spawn...) that registered on its
	// parent's channel: a controller of its own on channel, sharing
	// its parent's CPU scale. Its clock page goes to it in
	// page_fd_for_child, with the answer.
	static Result<std::unique_ptr<Controller>> adopt(int id, const Controller &parent, pid_t pid, UniqueFd channel,
							 const ControllerSpec &spec, int mode,
							 const ClockSetup &clocks, const RealtimePlan &rt,
							 const std::vector<BoundDevice> &devices);
	~Controller();

	int id = 0;
	int parent_id = 0; // the controller whose child it is (0: started by tcs)
	pid_t pid = -1;
	std::string name;
	double scale = 1.0;
	UniqueFd pidfd;
	UniqueFd channel;
	Mailbox mailbox; // its main thread's other way to the coordinator

	// The process's real CPU time now (ns), from its CPU-time clock.
	int64_t cpu_now() const;
	// Starts a new slice at the controller's current v and charge.
	void publish_slice(int64_t cpu_base);
	// CPU of the current slice that is not the program's (what a stop and
	// its continuation cost it in the kernel): not charged (negative: some
	// of what was left out charged after all). While stopped.
	void leave_out(int64_t ns);
	// What the current slice has left out so far, net of what was charged
	// back: no more can be charged back (tcs_less_own never adds).
	int64_t left_out() const { return left_out_; }
	// Of the current slice's CPU up to cpu, how much came after its clock
	// reads last told it a time (at most, cpu mode; none known elsewhere):
	// a stop's cost can be no more, as the stop came after that read.
	int64_t cpu_since_told(int64_t cpu) const;
	void set_page_flag(uint32_t flag, bool on);
	// Signals raised in it by the coordinator (the page's signals_raised).
	void count_raised_signal();
	uint64_t raised_signals() const { return signals_raised_; }
	// Its own wait (wait.active) as a side wait.
	Request own_wait() const;
	const tcs_slice &slice() const { return slice_; }
	// Real CPU the current slice has used up to cpu (the runtime's own cost
	// excluded: its hooks' and its CPU-clock reads').
	int64_t slice_cpu(int64_t cpu) const;
	// Where its current slice has taken it by CPU cpu (cpu mode's measure).
	int64_t v_at_cpu(int64_t cpu) const;
	// Its virtual time now: v, or while it runs, where its slice has
	// reached (its CPU so far in cpu mode; what spinning reached in lockstep).
	int64_t v_now(int mode) const;
	// Closes the slice at cpu: v and charged move forward, never back (in
	// lockstep, v to what spinning reached: spun()).
	void account(int64_t cpu, int mode);
	// Lockstep: how far spinning may take it in this slice (the page's
	// spin_limit), and how far it did (the page's spin_v, held to that
	// limit and to v: the controller's word).
	void limit_spin(int64_t until);
	int64_t spin_limit() const { return spin_limit_; }
	int64_t spun() const;
	// --seed: the key of its next child (each its own stream), or 0.
	uint64_t next_child_random_key();
	// The CPU up to which its request after its last fork charges it (the
	// page's fork_claim), if that is in the current slice; else -1.
	int64_t fork_claim() const;
	// The slice began with a WAKE whose hook has not yet marked its return
	// (the page's exit_cpu): all it has run of the slice is the hook's.
	bool returning_from_wait() const;
	// The coordinator ran on the controller's core: its CPU-time estimates
	// from before are stale (TCS_PAGE_CPU_ESTIMATE).
	void coordinator_ran();
	// Device handles it wrote without a round trip (lockstep), cleared.
	uint64_t take_lazy_handles();
	uint64_t quick_waits() const;
	uint64_t past_deadlines() const;
	// cpu mode: the latest time its clock reads returned, which an estimate
	// of its CPU may put ahead of v_now by one estimate's span at most.
	int64_t v_told(int mode) const;
	// Seconds its threads have waited in round trips for an answer (page).
	uint64_t unanswered_waits() const;
	// --record, --replay: its journal (null: none), and how many entries
	// it holds; recording, the next entry to drain (record_replay.cc).
	tcs_journal *journal() const { return journal_; }
	uint64_t journal_capacity() const { return journal_capacity_; }
	uint64_t journal_tail = 0;
	bool journal_lost = false; // recording: it could not keep an entry (said)
	std::vector<tcs_journal_entry> journal_batch; // drained, not yet in the record
	bool departed = false; // replaying: its departure has been said
	size_t commands_replayed = 0; // replaying: its commands compared so far
	void set_page_mode(int mode);
	// Ended: its descriptors and shared memory go back (a daemon serves
	// controllers for as long as it runs); what the report needs stays.
	void release();

	// Scheduling state: its state (written by transitions.cc's move()
	// alone), and what it waits in.
	CtlState state() const { return state_; }
	OwnWait wait; // the request being served, and what ends it when Blocked
	bool stopped = true;    // held by SIGSTOP
	bool hook_marks_return = false;  // its slice began with a WAKE, whose hook marks its return
	bool attached = false;  // the preload said HELLO
	int64_t hello_nonce = 0; // the current image's HELLO
	// Its virtual time (exact whenever not Running): moved by account() as
	// a slice closes and by transitions.cc alone otherwise.
	int64_t v() const { return v_; }
	int64_t charged = 0;    // virtual CPU charged
	int64_t budget = 0;     // real CPU this slice may use (cpu mode)
	// Where the current scheduling slice began, for the trace (a device
	// request answered at once restarts the accounting slice, not this).
	int64_t trace_wall_start = 0, trace_v_start = 0, trace_charged_start = 0, trace_cpu_start = 0;
	// Its CPU where its last slice ended (a wait's charge point, or the
	// reading that closed a preemption): the next slice begins there, so
	// that no CPU falls between two slices uncharged (-1: read it then).
	int64_t cpu_at_end = -1;
	int64_t resumed_wall = 0;  // wall ns when it was last resumed
	int64_t slice_wall = 0;    // wall ns when its accounting slice began
	int64_t slice_host_cpu = -1; // in the home lane: our own CPU then (slices.cc)
	int64_t checked_used = -1;  // slice CPU at the last budget check (-1: none yet)
	int64_t lag_ns = 0;         // learnt wall-versus-CPU lag of a slice
	int64_t check_interval = 0; // wall time until the next check
	// Threads: their channels, the waits of threads beside the controller's
	// own, and whether it is blocked with threads asleep outside the hooks.
	ChannelState main_state;
	std::vector<std::unique_ptr<ThreadChannel>> threads;
	std::vector<Request> side_waits;
	bool others_asleep = false;
	// Threads seen without a channel: when first seen (wall ns).
	std::map<pid_t, int64_t> thread_first_seen;
	uint32_t thread_registrations = 0;
	// It has started threads (or has thread channels): each wait looks at
	// them all.
	bool multithreaded() const;
	// The state of its channel fd: the main one's, or a thread's.
	ChannelState &channel_state(int fd);
	// The earliest deadline of its threads' waits beside its own.
	int64_t side_next() const;
	// A thread's wait w ends by virtual time `at` (the world at sim_ns).
	bool side_due(const Request &w, int64_t at, int64_t sim_ns) const;
	bool child_ended = false;     // a child ended while it was not waiting for one
	int64_t child_ended_at = 0;   // the latest such child's virtual time at its end
	bool runs_unhooked = false;   // its program runs without the preload: real time
	// Children seen running outside tcs: when first seen (wall ns; -1: said).
	std::map<pid_t, int64_t> unregistered_children;
	// Devices: what this controller has open (handle = index), and a
	// device request it is waiting on (for the world, or for a record).
	std::vector<std::unique_ptr<OpenDevice>> devices;
	std::optional<DeviceSync> sync;

	std::array<SignalTimer, TCS_MAX_TIMERS> timers;
	// The earliest expiry (TCS_NEVER: none), kept as timers change: the
	// scheduler asks on every decision.
	int64_t next_timer() const { return next_timer_; }
	void timers_changed();
	// The signals its timers due by v owe, as bits (n - 1 for signal n),
	// the timers moved past v: a waiting controller raises them itself,
	// each to its timer's thread.
	uint64_t take_due_timer_signals();
	// A thread a timer due by `at` signals (0: none names one).
	pid_t due_timer_thread(int64_t at) const;
	// The signals its timers due by v owe, sent (it is not waiting: stopped,
	// or about to run), each to the thread its timer names.
	void raise_due_timers();
	// A wait with its own signal mask looked for pending signals before one
	// of ours was raised (a preemption between its look and its BLOCK): the
	// kernel would have ended it at once, so it must look again before any
	// time passes (answered RECHECK at its own time).
	bool missed_raised_signal(const ::tcs_msg &m) const;
	// Blocked, it has been sent a signal at virtual time `at`: its waits
	// are re-checked then (an asleep one is looked at then).
	void note_signal(int64_t at);
	// Its threads' waits beside its own are to end, to re-check (a signal
	// may be theirs).
	void recheck_side_waits();
	bool budgeted = false;      // Running with a budget timer
	int lane = -1;  // Running: the coordinator's lane it runs in (lanes.cc)
	int core = -1;  // the core its threads were last pinned to (-1: not by us)
	uint64_t slices = 0; // how many times it was resumed
	// Real CPU it used in a turn on a core (the less of its last two), in
	// its last, and its charge when this one began (lanes.cc).
	int64_t turn_cpu = 0, last_turn_cpu = 0, charged_at_turn = 0;

	int exit_status = -1;   // wait status when Exited
	bool ended_by_tcs = false; // exited after the run's end was called
	int64_t kill_after = 0;    // wall time: SIGKILL then if still alive (0: no)
	std::string dropped;    // why tcs dropped it, if it did
	LoopStats stats;

	UniqueFd page_fd_for_child; // adopted: its page, until sent
	int64_t next_timer_ = TCS_NEVER;
	int64_t spin_limit_ = 0;
	uint64_t random_key_ = 0;
	uint64_t children_keyed_ = 0;
	bool woke_unheld = false; // woken from asleep, Ready but not held: answered as resumed
	// Its lane watchdog's last look at it, running (asleep.cc).
	struct Look {
		int64_t cpu = 0;      // its CPU then
		uint64_t slice = 0;   // the slice it was in
		int asleep_times = 0; // looks in a row that found it asleep
	} watchdog_look;
	// The stuck watchdog's last look at it (stuck.cc).
	struct StuckLook {
		uint64_t unanswered = 0; // the page's count then
		int64_t counted_at = 0;  // wall time it last grew
		int64_t since = 0;       // wall time it was first found stuck (0: not)
	} stuck;
	// Right after a fork: the child not yet registered (children.cc).
	struct NewChild {
		pid_t pid = 0;      // (0: none)
		UniqueFd pidfd;     // it may die before it registers
		int64_t since = 0;  // wall time
		bool exec = false;  // its exec not yet done: looked at
		uint32_t seq = 0;   // the parent's request to answer then, and
		int fd = -1;        // its channel (another thread's request may come meanwhile)
	} new_child;

private:
	friend bool move(Run &run, Controller &c, CtlMove m);
	friend void advance(Controller &c, int64_t at);
	friend void place_at(Controller &c, int64_t at);
	CtlState state_ = CtlState::Ready;
	int64_t v_ = 0;
	template <class F> void advance_due(F f);
	Result<UniqueFd> make_page(const ControllerSpec &spec, int mode, const ClockSetup &clocks,
				   const RealtimePlan &rt, const std::vector<BoundDevice> &bound);
	Status take_pid(pid_t p);
	tcs_clock_page *page_ = nullptr;
	int64_t left_out_ = 0; // (left_out())
	tcs_journal *journal_ = nullptr;
	uint64_t journal_bytes_ = 0, journal_capacity_ = 0;
	Status make_journal(int page_fd, const ControllerSpec &spec);
	void unmap();
	uint64_t signals_raised_ = 0;
	uint64_t final_quick_waits_ = 0, final_past_deadlines_ = 0; // once released
	clockid_t cpu_clock_ = 0;
	tcs_slice slice_ = {};
};

} // namespace tcs
