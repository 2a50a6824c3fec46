// measure_stop_cost(): a forked stand-in reads its own CPU-time clock in a
// loop and writes each reading to shared memory. Stopped, its CPU clock
// (exact: a stopped thread's count is brought up to date as it leaves its
// core) exceeds its last reading by the stop's cost; continued, its first
// reading exceeds that by the continuation's. Each bracket also holds part
// of one turn of its loop, which is taken off.
#include "stop_cost.h"

#include <sched.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <vector>

#include "clock_ns.h"

namespace tcs {

namespace {
// A stop's cost is spread over modes (12, 20 and 29 us on one VM, from one
// core to itself), so what is left out is a mean, of the middle of
// kRounds (kTrim dropped at either end: a round the machine disturbed).
constexpr int kRounds = 31;
constexpr int kTrim = 4;
// Readings the stand-in keeps (a few thousand turns: more than it makes
// while we look, at a turn of 0.2 us or more).
constexpr size_t kRing = 8192;
// How long it computes between stops, and the most we wait for it.
constexpr int64_t kRunFor = 100 * TCS_NS_PER_US;
constexpr int64_t kGiveUp = 100 * TCS_NS_PER_MS;

struct Shared {
	uint64_t count; // readings written
	std::array<int64_t, kRing> ring;
};

[[noreturn]] void stand_in(Shared *sh, const RealtimePlan &plan, int core)
{
	if (core >= 0) {
		cpu_set_t one;
		CPU_ZERO(&one);
		CPU_SET(core, &one);
		sched_setaffinity(0, sizeof one, &one);
	}
	apply_controller_realtime(plan);
	for (uint64_t n = 0;; n++) {
		struct timespec ts;
		clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
		sh->ring[n % kRing] = tcs_ts_to_ns(&ts);
		__atomic_store_n(&sh->count, n + 1, __ATOMIC_RELEASE);
	}
}

uint64_t count_of(const Shared *sh)
{
	return __atomic_load_n(&sh->count, __ATOMIC_ACQUIRE);
}

// Until it has written `n` readings, sleeping meanwhile ever longer: it may
// share our core, where waking often would leave it none (a wake-up costs
// some 20 us on a VM); false if it never does.
bool wait_for(const Shared *sh, uint64_t n)
{
	const int64_t until = clock_ns(CLOCK_MONOTONIC) + kGiveUp;
	int64_t pause_ns = 20 * TCS_NS_PER_US;
	while (count_of(sh) < n) {
		if (clock_ns(CLOCK_MONOTONIC) > until)
			return false;
		struct timespec pause = { 0, pause_ns };
		nanosleep(&pause, nullptr);
		pause_ns = std::min<int64_t>(2 * pause_ns, TCS_NS_PER_MS);
	}
	return true;
}

int64_t median(std::vector<int64_t> v)
{
	std::nth_element(v.begin(), v.begin() + (long)(v.size() / 2), v.end());
	return v[v.size() / 2];
}

int64_t middle_mean(std::vector<int64_t> v)
{
	std::sort(v.begin(), v.end());
	int64_t sum = 0;
	for (size_t i = kTrim; i < v.size() - kTrim; i++)
		sum += v[i];
	return sum / (int64_t)(v.size() - 2 * kTrim);
}

bool stopped(pid_t pid)
{
	siginfo_t si = {};
	int r;
	do
		r = waitid(P_PID, (id_t)pid, &si, WSTOPPED);
	while (r < 0 && errno == EINTR);
	return r == 0 && si.si_code == CLD_STOPPED;
}

// The rounds, on a running stand-in; false if it misbehaved.
bool rounds(Shared *sh, pid_t pid, clockid_t clock, std::vector<int64_t> &stops, std::vector<int64_t> &conts,
	    std::vector<int64_t> &turns)
{
	if (!wait_for(sh, 64))
		return false;
	for (int r = 0; r < kRounds; r++) {
		// A stretch of plain turns, then the stop.
		const uint64_t before = count_of(sh);
		struct timespec run = { 0, kRunFor };
		nanosleep(&run, nullptr);
		const uint64_t after = count_of(sh);
		if (after > before + 1)
			turns.push_back((sh->ring[(after - 1) % kRing] - sh->ring[before % kRing]) /
					(int64_t)(after - 1 - before));
		kill(pid, SIGSTOP);
		if (!stopped(pid))
			return false;
		struct timespec ts;
		if (clock_gettime(clock, &ts) != 0)
			return false;
		const int64_t at = tcs_ts_to_ns(&ts);
		const uint64_t seen = count_of(sh);
		kill(pid, SIGCONT);
		if (!wait_for(sh, seen + 2))
			return false;
		// The last reading before the stop and the first after it (one
		// may be written whose count was not yet when it stopped).
		int64_t last = -1, first = -1;
		for (uint64_t i = seen > 2 ? seen - 2 : 0; i < seen + 2; i++) {
			const int64_t t = sh->ring[i % kRing];
			if (t <= at)
				last = std::max(last, t);
			else if (first < 0)
				first = t;
		}
		if (last < 0 || first < 0)
			return false;
		stops.push_back(at - last);
		conts.push_back(first - at);
	}
	return true;
}
} // namespace

StopCost measure_stop_cost(const RealtimePlan &plan, int core)
{
	void *mem = mmap(nullptr, sizeof(Shared), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
	if (mem == MAP_FAILED)
		return {};
	auto *sh = static_cast<Shared *>(mem);
	StopCost cost;
	const pid_t pid = fork();
	if (pid == 0)
		stand_in(sh, plan, core);
	clockid_t clock;
	std::vector<int64_t> stops, conts, turns;
	if (pid > 0 && clock_getcpuclockid(pid, &clock) == 0 && rounds(sh, pid, clock, stops, conts, turns) &&
	    !turns.empty()) {
		// Each bracket holds the rest of one turn: half of one, on average.
		const int64_t half_turn = median(turns) / 2;
		cost.stop_ns = std::max<int64_t>(middle_mean(stops) - half_turn, 0);
		cost.continue_ns = std::max<int64_t>(middle_mean(conts) - half_turn, 0);
	}
	if (pid > 0) {
		kill(pid, SIGKILL);
		siginfo_t si;
		while (waitid(P_PID, (id_t)pid, &si, WEXITED) < 0 && errno == EINTR)
			;
	}
	munmap(mem, sizeof(Shared));
	return cost;
}

} // namespace tcs
