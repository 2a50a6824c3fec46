// The coordinator: owns virtual time, spawns and schedules controllers with
// SIGSTOP/SIGCONT and CPU budgets, serves their waits, and advances the
// world in fixed steps under conservative synchronisation (docs/DESIGN.md §2).
// tcs-run uses it in-process; it never prints: it reports.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <deque>
#include <map>
#include <tuple>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "agents.h"
#include "controller.h"
#include "duration_stats.h"
#include "device_server.h"
#include "sim_world.h"
#include "step_peers.h"
#include "trace.h"
#include "error.h"
#include "event_loop.h"
#include "lanes.h"
#include "polling.h"
#include "realtime.h"
#include "scheduler.h"
#include "tcs/clock_page.h"
#include "tcs/protocol.h"

namespace tcs {

struct ControllerReport;

struct CoordinatorConfig {
	int mode = TCS_MODE_CPU;
	int64_t step_ns = 1000000;          // the simulation step dt
	std::vector<ModelInstance> models;  // the world (none: an empty world)
	std::vector<DeviceConfig> devices;  // its virtual devices
	std::string trace_path;             // write an MCAP trace there (empty: none)
	int64_t duration_ns = -1;           // stop at this virtual time; < 0: when all exit
	std::optional<int64_t> epoch_ns;    // CLOCK_REALTIME at V = 0; default: now
	std::string preload;                // absolute path of libtcs_preload.so
	RealtimeWish realtime; // SCHED_FIFO and the TSC, where the machine allows
	// Called about every 250 ms of wall time while running (may be empty).
	std::function<void(int64_t virtual_ns, int64_t wall_ns)> on_progress;
	// Called once per distinct warning (may be empty).
	std::function<void(const std::string &)> on_warning;
	// coordinatord: the run lasts until a signal ends it, controllers come
	// and go (attach()), and a world without any runs at real-time speed.
	bool serve = false;
	// Called when the run's end begins (a signal, the duration).
	std::function<void()> on_ending;
	// A world shared with agents on other hosts (the host's end), or the
	// world of a host elsewhere (an agent's end: the models are then only
	// a mirror its grants fill). At most one; owned by the caller.
	StepHost *step_host = nullptr;
	StepAgent *step_agent = nullptr;
	// Host: the programs an agent runs now (the world may wait for them).
	std::function<void(const std::string &agent, const std::vector<std::string> &programs)> on_agent_controllers;
	// What a daemon logs: agents joining and leaving.
	std::function<void(const std::string &)> on_info;
	// Called when a controller tcs started (not a child of one) has ended.
	std::function<void(const ControllerReport &)> on_controller_end;
	// Called after each step of the world, with the time it has reached
	// (may be empty; it must not block: the run's loop calls it).
	std::function<void(int64_t sim_ns, const SimWorld &world)> on_step;
};

struct ControllerReport {
	int id = 0;
	pid_t pid = -1;
	std::string name;
	int wait_status = -1;     // as from waitpid; -1 if it never ended by itself
	bool ended_by_tcs = false; // stopped by tcs at the end of the run
	bool child = false;        // a child of a controller (its status is not tcs-run's)
	std::string dropped;      // non-empty: tcs dropped it, and why
	bool attached = false;    // libtcs_preload reported in
	int64_t virtual_ns = 0;
	int64_t charged_ns = 0;
	uint64_t waits = 0;           // waits served (including those that returned at once)
	uint64_t periodic_waits = 0;  // absolute-deadline waits (a periodic loop's cycles)
	uint64_t deadline_misses = 0; // absolute deadlines already past when asked for
	uint64_t preemptions = 0;
};

// Lost: a peer of the step protocol went silent (RunReport::lost says which).
enum class EndReason { AllExited, Duration, Signal, Lost };

struct RunReport {
	EndReason reason = EndReason::AllExited;
	int signal = 0; // EndReason::Signal
	int64_t virtual_ns = 0;
	int64_t wall_ns = 0;
	int64_t steps = 0;
	// Wall-clock cost of the world's steps (ns; zero for an empty world).
	int64_t step_wall_min = 0, step_wall_median = 0, step_wall_max = 0;
	RealtimePlan realtime;
	std::vector<ControllerReport> controllers;
	std::string lost; // EndReason::Lost: who, and what it means
};

class Coordinator {
public:
	static Result<std::unique_ptr<Coordinator>> create(CoordinatorConfig config);
	~Coordinator();

	// Spawns a controller (held stopped until run()).
	Status add_controller(const ControllerSpec &spec);
	// Runs until every controller has exited, the duration is reached, or a
	// signal ends the run; every controller is gone when it returns.
	Result<RunReport> run();

	// Serving (coordinatord), from handlers the run's loop calls:
	struct Attached {
		int id = 0;
		pid_t pid = -1;
	};
	// Starts a controller in the running world, at the world's time.
	Result<Attached> attach(const ControllerSpec &spec);
	// While held, nothing runs and the world does not step.
	void hold(bool on);
	// Sends signo to controller id for its caller (Ctrl-C at tcs-run).
	void signal_controller(int id, int signo);
	// Its caller has gone: SIGTERM now, SIGKILL after the end's grace.
	void end_controller(int id);
	// Another fd for the run's loop (a socket, a client).
	Status watch(int fd, std::function<void()> on_ready);
	void unwatch(int fd);
	int64_t sim_time() const { return sim_ns_; }
	int mode() const { return cfg_.mode; }
	int fifo_cpu() const { return rt_.fifo ? rt_.cpu : -1; }

private:
	Coordinator() = default;
	Status init();

	// Set-up, the run and its end, signals and progress, the report (coordinator.cc).
	void on_signal();
	void on_progress();
	ControllerReport report_of(const Controller &c) const;
	void warn_once(const std::string &what);
	int64_t alive_controllers() const;
	void begin_end(EndReason reason, int signo = 0);
	int64_t alive() const;

	// A controller's messages (messages.cc).
	// A message on the main channel (t == nullptr) or a thread's.
	void on_channel(Controller &c, ThreadChannel *t);
	// A request, from a channel or c's mailbox (t == nullptr).
	void on_request(Controller &c, ThreadChannel *t, const ::tcs_msg &m, UniqueFd passed);
	void on_message(Controller &c, const ::tcs_msg &m, int fd, pid_t tid);
	bool take_mailbox(Controller &c);

	// A controller's end (exits.cc).
	int64_t exited_cpu(const Controller &c);
	void on_pidfd(Controller &c);
	void on_exit(Controller &c, int wait_status);
	void drop(Controller &c, const std::string &why);

	// Children of controllers (children.cc).
	void on_child(Controller &parent, const ::tcs_msg &m, UniqueFd channel);
	void on_forked(Controller &c, const ::tcs_msg &m);
	void on_exec_look();
	void child_settled(Controller &parent);
	bool has_real_time_child(Controller &c);
	void child_wait_begins(Controller &c, const ::tcs_msg &m, SideWait *side);

	// The world's steps, as scheduler.h decides (world_steps.cc).
	void schedule();
	bool run_best(Controller &best, int64_t at, int64_t until);
	Contender contender_of(const Controller &c) const;
	bool advance_to(int64_t next);
	int64_t next_run_at(const Controller &c) const;
	void on_idle();
	void arm_idle_step();
	void apply_commands(int64_t boundary);
	Status step_world();

	// Slices: budgets, checks, preemption, accounting (slices.cc).
	void resume(Controller &c, int64_t target, int lane);
	void on_budget(Lane &lane);
	// SIGSTOP, and wait till it has stopped: false if it died first.
	bool hold(Controller &c);
	// Ends c's slice, stopping it unless held already (by hold()).
	void preempt(Controller &c, bool held = false);
	bool wait_until_stopped(Controller &c);
	// cpu: the process's CPU clock at the end; budget and overshoot: of a
	// preempted slice (real CPU).
	void trace_slice_end(Controller &c, const char *why, int64_t cpu, int64_t budget = -1, int64_t overshoot = 0);
	static int64_t wall_now();
	// The CPU a request charges up to; a claim may exceed the wall time
	// since the slice began by this much (the hook's part before we ran).
	int64_t charge_point(Controller &c, int64_t claimed);
	// When a request of a running controller's thread was made: its own
	// claim, no earlier than c.v nor later than its process's time as the
	// request is heard (other threads may have run since). c.v unless
	// running in cpu mode.
	int64_t request_v(Controller &c, const ::tcs_msg &m);

	// Waits: BLOCK, EARLY, WAKE (waits.cc).
	void on_block(Controller &c, const ::tcs_msg &m, int fd, pid_t tid);
	void on_early(Controller &c, const ::tcs_msg &m, int fd);
	void wake(Controller &c, int64_t v, uint16_t reason);
	void send_wake(Controller &c);
	void send_answer(Controller &c, int fd, const ::tcs_msg &m, int pass_fd);

	// Threads: their channels and waits beside the controller's (threads.cc).
	void hear_threads(Controller &c);
	void on_thread(Controller &c, const ::tcs_msg &m, UniqueFd channel);
	void thread_gone(Controller &c, ThreadChannel *t);
	bool side_wait(Controller &c, const ::tcs_msg &m, int fd, pid_t tid);
	void demote_wait(Controller &c);
	bool wake_threads(Controller &c, int64_t at);
	void end_side_waits(Controller &c);
	void answer_side(Controller &c, const SideWait &w);
	bool block_if_all_waiting(Controller &c);
	void end_all_side_waits(Controller &c);
	int runnable_threads(Controller &c, pid_t also);

	// Signal timers (signal_timers.cc).
	void on_timer(Controller &c, const ::tcs_msg &m);
	void budget_to_next_timer(Controller &c);

	// Signals between controllers (signals.cc).
	void on_kill(Controller &c, const ::tcs_msg &m);

	// Asleep in the kernel outside the hooks (asleep.cc).
	void arm_watchdog(Controller &c);
	void on_watchdog(Lane &lane);
	bool look_at(Controller &c);
	bool step_aside_if_asleep(Controller &c);
	bool still_asleep(Controller &c, int64_t at);
	void wake_from_asleep(Controller &c);

	// Devices: what a controller asks of them (device_requests.cc).
	void on_dev_open(Controller &c, const ::tcs_msg &m);
	void on_dev_sync(Controller &c, const ::tcs_msg &m);
	bool complete_sync(Controller &c);
	void reply_now(Controller &c, int64_t arg);
	void restart_slice(Controller &c, int64_t request_cpu);

	// Peers on other hosts, both ends (remote.cc; agents.h: the host's agents).
	void on_step_host();
	void on_step_agent();
	bool agents_answered() const;
	void grant_now();
	void answer_grant();
	void word_of_controllers();
	void lose(const std::string &why);

	// Serving, for coordinatord (serve.cc).
	Controller *top_level(int id);
	bool descends_from(const Controller &o, int root) const;

	// Constants, and state the parts above share.
	std::vector<Contender> contenders_; // (kept: schedule() runs on every request)
	bool hearing_ = false; // hear_threads: schedule() waits for the last
	// The shortest slice worth a timer. A timer cycle (interrupt, wake-up,
	// CPU-clock read, re-arm) costs a few microseconds of the same core, so a
	// shorter slice would leave the controller almost nothing of it: with
	// SCHED_FIFO it would never get to run at all. The overshoot this allows
	// is carried into the next budget like any other.
	static constexpr int64_t kMinSlice = 20 * TCS_NS_PER_US;
	// The longest a parent waits for its new child to register (wall time).
	static constexpr int64_t kRegistrationWait = 1 * TCS_NS_PER_S;
	// How long controllers get to act on SIGTERM at the end before SIGKILL.
	static constexpr int64_t kEndGrace = 2 * TCS_NS_PER_S;
	// How often a lane's watchdog looks at those running: asleep.cc.
	static constexpr int64_t kWatchdog = 2 * TCS_NS_PER_MS;
	// How far a request's CPU claim may exceed the wall time since its slice
	// began: the hook's part before the coordinator ran (charge_point).
	static constexpr int64_t kClaimSlack = 1 * TCS_NS_PER_MS;

	CoordinatorConfig cfg_;
	RealtimePlan rt_;
	ClockOrigins origins_;
	EventLoop loop_;
	// The coordinator's core's first (its controller's estimates go stale
	// whenever the coordinator runs).
	Lanes lanes_;
	MailboxPoller poller_;
	Timer progress_timer_;
	Timer kill_timer_;
	Timer idle_timer_;
	// A world running at real-time speed: the wall time its steps are
	// due at (arm_idle_step).
	struct IdlePace {
		int64_t wall = 0, sim = 0; // where it began
		int64_t next_sim = -1; // the step it was armed for
		int64_t wall_for(int64_t at) const { return wall + (at - sim); }
	} idle_;
	// Fires at once: a long way for the world to go is computed in slices
	// of wall time, with the event loop (signals, deaths) served between.
	Timer continue_timer_;
	// A multi-threaded controller whose main thread has ended reads as
	// ended on its pidfd before its other threads have: looked at again
	// from this timer (not in a loop: on our core, at our priority, they
	// would never get to end).
	Timer exit_timer_;
	Timer exec_timer_; // a new child's exec, still under way
	std::vector<Controller *> exiting_;
	UniqueFd signal_fd_;
	std::vector<std::unique_ptr<Controller>> ctls_;
	std::unique_ptr<SimWorld> world_;
	DeviceServer devices_;
	DurationStats step_walls_; // wall cost of each world step
	Trace trace_;
	std::vector<size_t> joint_signals_;
	std::vector<std::string> warned_;

	int64_t sim_ns_ = 0;    // S: the simulation clock
	int64_t steps_ = 0;
	bool ending_ = false;
	bool held_ = false;
	Agents agents_; // host: the agents taking part
	// Agent: answered, and the next grant not here yet (at first: none yet).
	bool awaiting_grant_ = false;
	bool granted_ = false;
	std::vector<std::string> programs_; // its controllers' programs, as last told
	std::string lost_; // a peer gone: why the run ended
	EndReason end_reason_ = EndReason::AllExited;
	int end_signal_ = 0;
	int64_t wall_start_ = 0;
	Status fatal_ = Ok{};
};

} // namespace tcs
