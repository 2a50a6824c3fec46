// Controller: starting one (channel, clock page, spawn) and its accounting.
#include "controller.h"

#include <signal.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <time.h>

#include <algorithm>
#include <cstdio>

#include "device_server.h"
#include "spawn.h"
#include "tcs/device_table.h"
#include "tcs/random_stream.h"

namespace tcs {

// The shared region of a new controller: its clock page (set-once fields
// filled in) and its device table.
Result<UniqueFd> Controller::make_page(const ControllerSpec &spec, int mode, const ClockSetup &clocks,
				       const RealtimePlan &rt, const std::vector<BoundDevice> &bound)
{
	UniqueFd page_fd(memfd_create("tcs-clock-page", MFD_CLOEXEC));
	if (!page_fd)
		return errno_error("memfd_create");
	if (ftruncate(page_fd.get(), TCS_SHARED_SIZE) < 0)
		return errno_error("ftruncate");
	if (auto s = make_journal(page_fd.get(), spec); !s)
		return s.error();
	void *m = mmap(nullptr, TCS_SHARED_SIZE, PROT_READ | PROT_WRITE, MAP_SHARED, page_fd.get(), 0);
	if (m == MAP_FAILED)
		return errno_error("mmap");
	page_ = static_cast<tcs_clock_page *>(m);
	mailbox.attach(&page_->mailbox);
	page_->magic = TCS_PAGE_MAGIC;
	page_->version = TCS_PAGE_VERSION;
	page_->mode = (uint32_t)mode;
	page_->flags = (spec.report_misses ? TCS_PAGE_REPORT_MISSES : 0) | (rt.cpu_estimate() ? TCS_PAGE_CPU_ESTIMATE : 0) |
		       (rt.ticks == EstimateTicks::Vdso ? TCS_PAGE_TICKS_VDSO : 0) |
		       (rt.fifo && rt.cpu >= 0 ? TCS_PAGE_FIFO | TCS_PAGE_SHARES_CORE : 0) |
		       (spec.replay ? TCS_PAGE_REPLAY : 0);
	page_->journal_bytes = journal_bytes_;
	page_->tick_mult = rt.tick_mult;
	page_->tick_resync = rt.tick_resync;
	page_->cpu_scale = spec.cpu_scale;
	page_->mono_origin_ns = clocks.mono_ns;
	page_->real_origin_ns = clocks.real_ns;
	page_->tai_origin_ns = clocks.tai_ns;
	page_->random_key = random_key_ = spec.random_key;
	page_->spin_clock_ns = (int32_t)clocks.spin.clock_ns;
	page_->spin_read_ns = (int32_t)clocks.spin.read_ns;
	tcs_device_table *table = tcs_device_table_of(page_);
	for (const auto &d : bound) {
		if (table->count == TCS_MAX_DEVICES)
			break;
		tcs_device_entry &e = table->dev[table->count++];
		snprintf(e.path, sizeof e.path, "%s", d.cfg.path.c_str());
		e.kind = (uint32_t)d.cfg.kind;
		e.format = (uint32_t)d.cfg.format;
		e.latest = d.cfg.latest ? 1 : 0;
		e.width = is_wire(d.cfg.kind) ? d.cfg.table_width : (uint32_t)d.width;
	}
	return page_fd;
}

// Its journal, after the device table in the same memory: a ring to record
// into, or the record's entries for it to replay.
Status Controller::make_journal(int page_fd, const ControllerSpec &spec)
{
	if (!spec.record && !spec.replay)
		return Ok{};
	uint64_t n = spec.record ? (TCS_JOURNAL_RING_BYTES - TCS_JOURNAL_HEADER) / sizeof(tcs_journal_entry)
				 : std::max<uint64_t>(spec.replay->size(), 1);
	uint64_t bytes = (tcs_journal_bytes(n) + 4095) / 4096 * 4096;
	if (ftruncate(page_fd, (off_t)(TCS_JOURNAL_OFFSET + bytes)) < 0)
		return errno_error("ftruncate (journal)");
	void *m = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, page_fd, TCS_JOURNAL_OFFSET);
	if (m == MAP_FAILED)
		return errno_error("mmap (journal)");
	journal_ = static_cast<tcs_journal *>(m);
	journal_bytes_ = bytes;
	journal_capacity_ = (bytes - TCS_JOURNAL_HEADER) / sizeof(tcs_journal_entry);
	journal_->magic = TCS_JOURNAL_MAGIC;
	journal_->capacity = journal_capacity_;
	if (spec.replay) {
		journal_->replaying = 1;
		std::copy(spec.replay->begin(), spec.replay->end(), tcs_journal_entries(journal_));
		journal_->tail = spec.replay->size();
	}
	return Ok{};
}

void Controller::set_page_mode(int mode)
{
	if (page_)
		__atomic_store_n(&page_->mode, (uint32_t)mode, __ATOMIC_RELEASE);
}

void Controller::unmap()
{
	if (journal_)
		munmap(journal_, journal_bytes_);
	journal_ = nullptr;
	if (page_)
		munmap(page_, TCS_SHARED_SIZE);
	page_ = nullptr;
}

Status Controller::take_pid(pid_t p)
{
	pid = p;
	page_->owner_pid = p;
	if (clock_getcpuclockid(pid, &cpu_clock_) != 0)
		return errno_error("clock_getcpuclockid");
	publish_slice(cpu_now());
	return Ok{};
}

Result<std::unique_ptr<Controller>> Controller::start(int id, const ControllerSpec &spec, int mode,
						      const ClockSetup &clocks, const RealtimePlan &rt,
						      const std::string &preload, const std::vector<BoundDevice> &devices)
{
	auto c = std::make_unique<Controller>();
	c->id = id;
	c->scale = spec.cpu_scale;
	c->name = spec.argv.empty() ? spec.path : spec.argv[0];

	int sv[2];
	if (socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, sv) < 0)
		return errno_error("socketpair");
	c->channel.reset(sv[0]);
	UniqueFd child_end(sv[1]);
	auto page_fd = c->make_page(spec, mode, clocks, rt, devices);
	if (!page_fd)
		return page_fd.error();

	SpawnRequest req;
	req.path = spec.path;
	req.argv = spec.argv;
	req.preload = preload;
	req.channel_fd = child_end.get();
	req.page_fd = page_fd->get();
	req.realtime = rt;
	req.env = spec.env ? &*spec.env : nullptr;
	req.cwd = spec.cwd;
	req.stdio = spec.stdio;
	auto spawned = spawn_stopped(req);
	if (!spawned)
		return spawned.error();
	c->pidfd = std::move(spawned->pidfd);
	if (auto s = c->take_pid(spawned->pid); !s)
		return s.error();
	return c;
}

Result<std::unique_ptr<Controller>> Controller::adopt(int id, const Controller &parent, pid_t pid, UniqueFd channel,
						      const ControllerSpec &spec, int mode, const ClockSetup &clocks,
						      const RealtimePlan &rt, const std::vector<BoundDevice> &devices)
{
	auto c = std::make_unique<Controller>();
	c->id = id;
	c->parent_id = parent.id;
	c->scale = parent.scale;
	c->name = parent.name; // until it execs another program
	c->channel = std::move(channel);
	auto page_fd = c->make_page(spec, mode, clocks, rt, devices);
	if (!page_fd)
		return page_fd.error();
	c->pidfd.reset((int)syscall(SYS_pidfd_open, pid, 0));
	if (!c->pidfd)
		return errno_error("pidfd_open");
	c->stopped = false; // it waits for its answer on its channel
	c->attached = true; // the CHILD was its hello (an exec brings another)
	if (auto s = c->take_pid(pid); !s)
		return s.error();
	c->page_fd_for_child = std::move(*page_fd);
	return c;
}

Controller::~Controller()
{
	if (wait.pass_fd >= 0)
		close(wait.pass_fd);
	if (state_ != CtlState::Exited && pid > 0) {
		kill(pid, SIGKILL); // never leave one behind, stopped or not
		siginfo_t si;
		waitid(P_PID, pid, &si, WEXITED);
	}
	unmap();
}

int64_t Controller::cpu_now() const
{
	struct timespec ts;
	if (clock_gettime(cpu_clock_, &ts) != 0)
		return slice_.cpu_base; // it has just exited: no further CPU
	return tcs_ts_to_ns(&ts);
}

Request Controller::own_wait() const
{
	Request w = wait;
	w.fd = wait.fd >= 0 ? wait.fd : channel.get();
	if (!wait.owed) // (an answer owed to it goes with it)
		w.reason = 0, w.result = 0;
	return w;
}

// After release() (an ended controller) there is no page: what follows
// touches nothing.
void Controller::set_page_flag(uint32_t flag, bool on)
{
	if (!page_ || ((__atomic_load_n(&page_->flags, __ATOMIC_RELAXED) & flag) != 0) == on)
		return;
	if (on)
		__atomic_fetch_or(&page_->flags, flag, __ATOMIC_RELEASE);
	else
		__atomic_fetch_and(&page_->flags, ~flag, __ATOMIC_RELEASE);
}

// The count is ours; the page holds a copy for the controller to read (what
// it writes there can only make its own waits look again).
void Controller::count_raised_signal()
{
	signals_raised_++;
	if (page_)
		__atomic_store_n(&page_->signals_raised, signals_raised_, __ATOMIC_RELEASE);
}

void Controller::publish_slice(int64_t cpu_base)
{
	slice_ = tcs_slice{ v_, cpu_base, charged, page_ ? __atomic_load_n(&page_->own_cpu, __ATOMIC_RELAXED) : 0 };
	left_out_ = 0;
	if (page_)
		tcs_page_write_slice(page_, slice_);
}

void Controller::leave_out(int64_t ns)
{
	if (ns == 0)
		return;
	// As the runtime's own CPU is (tcs_less_own): the slice's CPU less
	// what the page's own_cpu has grown by since own_base.
	slice_.own_base -= ns;
	left_out_ += ns;
	if (page_)
		tcs_page_write_slice(page_, slice_);
}

int64_t Controller::cpu_since_told(int64_t cpu) const
{
	if (!page_)
		return 0;
	int64_t seen = __atomic_load_n(&page_->v_seen, __ATOMIC_RELAXED);
	int64_t ahead = v_at_cpu(cpu) - seen;
	if (ahead <= 0)
		return 0;
	return scale == 1.0 ? ahead : (int64_t)((double)ahead / scale);
}

int64_t Controller::slice_cpu(int64_t cpu) const
{
	if (!page_)
		return tcs_less_own(tcs_slice_cpu(slice_.cpu_base, 0, cpu), slice_.own_base, 0);
	return tcs_page_slice_cpu(page_, slice_, cpu);
}

int64_t Controller::v_at_cpu(int64_t cpu) const
{
	return tcs_ns_add(slice_.v_base, tcs_scale_cpu(slice_cpu(cpu), scale));
}

int64_t Controller::v_now(int mode) const
{
	if (state_ != CtlState::Running)
		return v_;
	return mode == TCS_MODE_CPU ? std::max(v_, v_at_cpu(cpu_now())) : spun();
}

int64_t Controller::v_told(int mode) const
{
	int64_t exact = v_now(mode);
	if (mode != TCS_MODE_CPU || !page_)
		return exact;
	// What its clock reads told it, no further ahead of the exact reading
	// than an estimate runs between two (its word, held to that).
	int64_t seen = __atomic_load_n(&page_->v_seen, __ATOMIC_RELAXED);
	int64_t span = (int64_t)(((unsigned __int128)page_->tick_resync * page_->tick_mult) >> 32);
	return std::clamp(seen, exact, tcs_ns_add(exact, tcs_scale_cpu(span, scale)));
}

void Controller::account(int64_t cpu, int mode)
{
	int64_t used = tcs_scale_cpu(slice_cpu(cpu), scale);
	if (mode == TCS_MODE_CPU)
		v_ = std::max(v_, tcs_ns_add(slice_.v_base, used));
	else
		v_ = spun();
	// Replaying, the record's charges are what moved it: its virtual time
	// in the slice, as in cpu mode (not this machine's CPU).
	if (page_ && (__atomic_load_n(&page_->flags, __ATOMIC_RELAXED) & TCS_PAGE_REPLAY))
		used = std::max<int64_t>(v_ - slice_.v_base, 0);
	charged = std::max(charged, tcs_ns_add(slice_.charged_base, used));
}

void Controller::limit_spin(int64_t until)
{
	spin_limit_ = until;
	if (page_)
		__atomic_store_n(&page_->spin_limit, until, __ATOMIC_RELEASE);
}

uint64_t Controller::next_child_random_key()
{
	return random_key_ ? tcs_random_key(random_key_, ++children_keyed_) : 0;
}

int64_t Controller::spun() const
{
	int64_t at = page_ ? __atomic_load_n(&page_->spin_v, __ATOMIC_ACQUIRE) : v_;
	return std::max(v_, std::min(at, spin_limit_));
}

int64_t Controller::fork_claim() const
{
	int64_t claim = page_ ? __atomic_load_n(&page_->fork_claim, __ATOMIC_RELAXED) : -1;
	return claim > slice_.cpu_base ? claim : -1;
}

bool Controller::returning_from_wait() const
{
	return hook_marks_return && page_ && __atomic_load_n(&page_->exit_cpu, __ATOMIC_RELAXED) < slice_.cpu_base;
}

uint64_t Controller::take_lazy_handles()
{
	if (!page_ || __atomic_load_n(&page_->lazy_handles, __ATOMIC_RELAXED) == 0)
		return 0;
	return __atomic_exchange_n(&page_->lazy_handles, 0, __ATOMIC_ACQ_REL);
}

void Controller::timers_changed()
{
	next_timer_ = TCS_NEVER;
	for (const auto &t : timers)
		next_timer_ = std::min(next_timer_, t.next);
}

void Controller::coordinator_ran()
{
	if (page_)
		tcs_page_bump_gen(page_);
}

bool Controller::multithreaded() const
{
	return !threads.empty() || (page_ && __atomic_load_n(&page_->threads_started, __ATOMIC_RELAXED) != 0);
}

uint64_t Controller::quick_waits() const
{
	return page_ ? __atomic_load_n(&page_->quick_returns, __ATOMIC_RELAXED) : final_quick_waits_;
}

uint64_t Controller::past_deadlines() const
{
	return page_ ? __atomic_load_n(&page_->past_deadlines, __ATOMIC_RELAXED) : final_past_deadlines_;
}

uint64_t Controller::unanswered_waits() const
{
	return page_ ? __atomic_load_n(&page_->unanswered, __ATOMIC_RELAXED) : 0;
}

void Controller::release()
{
	final_quick_waits_ = quick_waits();
	final_past_deadlines_ = past_deadlines();
	channel.reset();
	pidfd.reset();
	new_child.pidfd.reset();
	page_fd_for_child.reset();
	threads.clear();
	devices.clear();
	mailbox.attach(nullptr);
	unmap();
}

// Calls f with each timer due by v, then moves it past v: expirations
// that fell together are one signal, as pending signals of one kind are.
template <class F> void Controller::advance_due(F f)
{
	for (SignalTimer &t : timers) {
		if (t.next == TCS_NEVER || t.next > v_)
			continue;
		f(t);
		t.next = t.interval > 0 ? t.next + ((v_ - t.next) / t.interval + 1) * t.interval : TCS_NEVER;
	}
	timers_changed();
}

uint64_t Controller::take_due_timer_signals()
{
	uint64_t bits = 0;
	advance_due([&](const SignalTimer &t) { bits |= 1ull << (t.signo - 1); });
	return bits;
}

pid_t Controller::due_timer_thread(int64_t at) const
{
	for (const SignalTimer &t : timers)
		if (t.next <= at && t.tid > 0)
			return t.tid;
	return 0;
}

void Controller::raise_due_timers()
{
	advance_due([&](const SignalTimer &t) {
		if (t.tid > 0)
			syscall(SYS_tgkill, pid, t.tid, t.signo);
		else
			kill(pid, t.signo);
		count_raised_signal(); // (after: pending before it is counted)
	});
}

bool Controller::missed_raised_signal(const ::tcs_msg &m) const
{
	return (m.flags & TCS_BLOCK_SIGMASK) && (uint64_t)m.arg != signals_raised_;
}

void Controller::note_signal(int64_t at)
{
	wait.signalled_at = std::min(wait.signalled_at, at);
	recheck_side_waits();
}

void Controller::recheck_side_waits()
{
	for (Request &w : side_waits)
		if (w.reason == 0)
			w.reason = TCS_WAKE_RECHECK;
}

ChannelState &Controller::channel_state(int fd)
{
	for (auto &t : threads)
		if (t->fd.get() == fd)
			return t->state;
	return main_state;
}

int64_t Controller::side_next() const
{
	int64_t next = TCS_NEVER;
	for (const Request &w : side_waits)
		next = std::min(next, w.deadline);
	return next;
}

bool Controller::side_due(const Request &w, int64_t at, int64_t sim_ns) const
{
	return w.reason != 0 || w.deadline <= at || ((w.flags & TCS_BLOCK_RECHECK) && w.rechecked_at < sim_ns) ||
	       ((w.flags & TCS_BLOCK_DEVICES) && next_record_due(*this) <= at);
}

} // namespace tcs
