// dds_barrier [--rounds N] [--domain D] [--signals K] [--spread]: the wall
// time of one step barrier of the remote-agent protocol (coordinatord/dds/
// idl/tcs_step.idl) over Cyclone DDS on loopback: the host publishes
// StepGrant k with K signals, the agent answers StepDone k with one
// command, the host waits for it (a waitset) and grants k+1.
//
// The agent is a forked process with a DDS participant of its own, so each
// barrier crosses the loopback network stack as it would between hosts.
// Forking comes before any DDS call: Cyclone's threads do not survive a
// fork. Each side waits until both its endpoints have matched the other's;
// then the first grant is repeated until answered (a volatile reader can
// miss a sample written just as it was discovered), and a warm-up runs
// before the N timed barriers.
//
// Both processes, and Cyclone's threads in them, run on one core, as the
// ping-pong they are compared with does: on a virtual machine, a wake-up
// across cores costs the hypervisor's inter-processor interrupt, and where
// the scheduler places four threads on two cores changes the median
// threefold from one run to the next. --spread leaves them unpinned.
//
// Prints one line, rounds=N median_us=... p99_us=... min_us=...; judges
// nothing (bench/run.py sets it against the SOCK_SEQPACKET ping-pong).
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <dds/dds.h>

#include "bench_time.h"
#include "tcs_step.h"

namespace {

// Loopback alone, unicast discovery: works on a machine with no other
// interface and no multicast, and stays off any real network.
constexpr const char *loopback_uri =
	"<General><Interfaces><NetworkInterface name=\"lo\"/></Interfaces>"
	"<AllowMulticast>false</AllowMulticast></General>"
	"<Discovery><ParticipantIndex>auto</ParticipantIndex>"
	"<Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery>";

constexpr int64_t step_ns = 1'000'000;
constexpr dds_duration_t match_timeout = DDS_SECS(10);
constexpr dds_duration_t answer_timeout = DDS_SECS(10);
// How often the first grant is repeated until the agent answers it.
constexpr dds_duration_t hello_period = DDS_MSECS(100);

struct Options {
	long rounds = 5000;
	long warmup = 500;
	long signals = 4;
	long domain = -1; // default: 200 + pid % 30, a domain of this run's own
	bool spread = false;
};

struct Side {
	dds_entity_t participant = 0;
	dds_entity_t writer = 0;
	dds_entity_t reader = 0;
	dds_entity_t waitset = 0; // wakes on data in reader
};

double now_ns()
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

bool parse_long(const char *s, long min, long max, long &out)
{
	if (!s)
		return false;
	char *end;
	errno = 0;
	out = std::strtol(s, &end, 10);
	return errno == 0 && end != s && *end == '\0' && out >= min && out <= max;
}

bool parse(int argc, char **argv, Options &o)
{
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : nullptr;
		bool ok;
		if (!std::strcmp(a, "--spread")) {
			o.spread = true;
			continue;
		}
		if (!std::strcmp(a, "--rounds"))
			ok = parse_long(v, 1, 100'000'000, o.rounds);
		else if (!std::strcmp(a, "--domain"))
			ok = parse_long(v, 0, 232, o.domain);
		else if (!std::strcmp(a, "--signals"))
			ok = parse_long(v, 0, 1'000'000, o.signals);
		else
			return false;
		if (!ok)
			return false;
		i++;
	}
	return true;
}

// An error: what failed and Cyclone's reason; printed once, by main.
std::string dds_error(const char *what, dds_return_t rc)
{
	return std::string(what) + ": " + dds_strretcode(rc);
}

// The step protocol's QoS: nothing may be lost, so reliable and KEEP_ALL
// (a writer ahead of its readers blocks rather than overwrite); volatile,
// as a late agent has no use for old steps. XCDR2: the types are
// @appendable, which XCDR1 cannot carry.
dds_qos_t *step_qos()
{
	dds_qos_t *q = dds_create_qos();
	dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
	dds_qset_history(q, DDS_HISTORY_KEEP_ALL, 0);
	dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
	const dds_data_representation_id_t xcdr2 = DDS_DATA_REPRESENTATION_XCDR2;
	dds_qset_data_representation(q, 1, &xcdr2);
	return q;
}

// The participant, the writer of one topic and the reader of the other
// (the host writes grants and reads answers, the agent the reverse), and
// a waitset that wakes when the reader holds a sample.
std::string open_side(uint32_t domain, bool host, Side &s)
{
	s.participant = dds_create_participant(domain, nullptr, nullptr);
	if (s.participant < 0)
		return dds_error("creating the participant", s.participant);
	dds_entity_t grant = dds_create_topic(s.participant, &tcs_dds__StepGrant_desc, tcs_dds__STEP_GRANT_TOPIC,
					      nullptr, nullptr);
	if (grant < 0)
		return dds_error("creating the grant topic", grant);
	dds_entity_t done = dds_create_topic(s.participant, &tcs_dds__StepDone_desc, tcs_dds__STEP_DONE_TOPIC,
					     nullptr, nullptr);
	if (done < 0)
		return dds_error("creating the done topic", done);
	dds_qos_t *q = step_qos();
	s.writer = dds_create_writer(s.participant, host ? grant : done, q, nullptr);
	s.reader = dds_create_reader(s.participant, host ? done : grant, q, nullptr);
	dds_delete_qos(q);
	if (s.writer < 0)
		return dds_error("creating the writer", s.writer);
	if (s.reader < 0)
		return dds_error("creating the reader", s.reader);
	s.waitset = dds_create_waitset(s.participant);
	if (s.waitset < 0)
		return dds_error("creating a waitset", s.waitset);
	dds_entity_t cond = dds_create_readcondition(s.reader, DDS_ANY_STATE);
	if (cond < 0)
		return dds_error("creating a read condition", cond);
	dds_return_t rc = dds_waitset_attach(s.waitset, cond, 0);
	if (rc < 0)
		return dds_error("attaching the read condition", rc);
	return {};
}

// Waits (on the matched statuses, no polling) until this side's writer and
// reader have both matched the other side's: until then a sample written
// can be lost (volatile) and one sent to us dropped.
std::string wait_matched(const Side &s)
{
	dds_entity_t ws = dds_create_waitset(s.participant);
	if (ws < 0)
		return dds_error("creating a waitset", ws);
	dds_set_status_mask(s.writer, DDS_PUBLICATION_MATCHED_STATUS);
	dds_set_status_mask(s.reader, DDS_SUBSCRIPTION_MATCHED_STATUS);
	dds_waitset_attach(ws, s.writer, 0);
	dds_waitset_attach(ws, s.reader, 0);
	const dds_time_t deadline = dds_time() + match_timeout;
	std::string err = "the other process's endpoints did not match within 10 s";
	for (;;) {
		dds_publication_matched_status_t w{};
		dds_subscription_matched_status_t r{};
		dds_get_publication_matched_status(s.writer, &w);
		dds_get_subscription_matched_status(s.reader, &r);
		if (w.current_count > 0 && r.current_count > 0) {
			err.clear();
			break;
		}
		if (dds_waitset_wait_until(ws, nullptr, 0, deadline) <= 0)
			break;
	}
	dds_delete(ws);
	return err;
}

// Takes one sample (a loan) that has data. 1: got one; 0: none left;
// negative: a DDS error. Samples without data (an instance's state
// changing) are returned and skipped.
template <class T, class F>
dds_return_t take_one(dds_entity_t reader, F &&use)
{
	for (;;) {
		void *buf[1] = { nullptr };
		dds_sample_info_t info[1];
		dds_return_t n = dds_take(reader, buf, info, 1, 1);
		if (n <= 0)
			return n;
		bool valid = info[0].valid_data;
		if (valid)
			use(*static_cast<const T *>(buf[0]));
		dds_return_loan(reader, buf, n);
		if (valid)
			return 1;
	}
}

// The agent: answers each grant of this world with a StepDone carrying one
// command, until it has answered the last step.
std::string agent(const Options &o, uint32_t world, uint64_t last_step, Side &s)
{
	if (auto err = open_side(static_cast<uint32_t>(o.domain), false, s); !err.empty())
		return err;
	if (auto err = wait_matched(s); !err.empty())
		return err;
	static char name[] = "bench-agent";
	tcs_dds__Command cmd{};
	tcs_dds__StepDone done{};
	done.world = world;
	done.agent = name;
	done.commands = { 1, 1, &cmd, false };
	bool finished = false;
	while (!finished) {
		dds_return_t rc = dds_waitset_wait(s.waitset, nullptr, 0, answer_timeout);
		if (rc < 0)
			return dds_error("waiting for a grant", rc);
		if (rc == 0)
			return "no grant within 10 s";
		for (;;) {
			tcs_dds__StepGrant g{};
			rc = take_one<tcs_dds__StepGrant>(s.reader, [&](const tcs_dds__StepGrant &in) {
				g.world = in.world;
				g.step = in.step;
				g.sim_ns = in.sim_ns;
				// What a controller would act on: the first signal.
				cmd.value = in.signals._length ? -in.signals._buffer[0] : 0.0;
			});
			if (rc < 0)
				return dds_error("taking a grant", rc);
			if (rc == 0)
				break;
			if (g.world != world)
				continue; // another run's, in the same domain
			done.step = g.step;
			done.next_event_ns = g.sim_ns + step_ns;
			cmd.v_ns = g.sim_ns + step_ns / 2;
			cmd.signal = 0;
			if ((rc = dds_write(s.writer, &done)) < 0)
				return dds_error("writing StepDone", rc);
			finished = g.step == last_step;
		}
	}
	return {};
}

// Waits for the StepDone of `step` from this world's agent, skipping
// earlier ones (answers to the repeated first grant); `got` says whether
// it came before `deadline`.
std::string wait_done(const Side &s, uint32_t world, uint64_t step, dds_time_t deadline, bool &got)
{
	got = false;
	for (;;) {
		for (;;) {
			bool match = false;
			dds_return_t rc = take_one<tcs_dds__StepDone>(s.reader, [&](const tcs_dds__StepDone &d) {
				match = d.world == world && d.step == step && d.commands._length == 1;
			});
			if (rc < 0)
				return dds_error("taking a StepDone", rc);
			if (rc == 0)
				break;
			if (match) {
				got = true;
				return {};
			}
		}
		dds_return_t rc = dds_waitset_wait_until(s.waitset, nullptr, 0, deadline);
		if (rc < 0)
			return dds_error("waiting for StepDone", rc);
		if (rc == 0)
			return {};
	}
}

// The host: grants steps 0..last_step, times those from o.warmup on.
std::string host(const Options &o, uint32_t world, uint64_t last_step, Side &s, std::vector<double> &times)
{
	if (auto err = open_side(static_cast<uint32_t>(o.domain), true, s); !err.empty())
		return err;
	if (auto err = wait_matched(s); !err.empty())
		return err;
	std::vector<double> signals(static_cast<size_t>(o.signals));
	const auto k = static_cast<uint32_t>(o.signals);
	tcs_dds__StepGrant g{};
	g.world = world;
	// Lent to dds_write, which has serialised it when it returns.
	g.signals = { k, k, signals.data(), false };
	times.reserve(static_cast<size_t>(o.rounds));
	for (uint64_t step = 0; step <= last_step; step++) {
		g.step = step;
		g.sim_ns = static_cast<int64_t>(step) * step_ns;
		for (size_t i = 0; i < signals.size(); i++)
			signals[i] = static_cast<double>(step) + 0.125 * static_cast<double>(i);
		const dds_time_t give_up = dds_time() + answer_timeout;
		bool got = false;
		const double t0 = now_ns();
		while (!got) {
			dds_return_t rc = dds_write(s.writer, &g);
			if (rc < 0)
				return dds_error("writing StepGrant", rc);
			const dds_time_t deadline = step == 0 ? std::min(give_up, dds_time() + hello_period) : give_up;
			if (auto err = wait_done(s, world, step, deadline, got); !err.empty())
				return err;
			if (!got && dds_time() >= give_up)
				return "no StepDone for step " + std::to_string(step) + " within 10 s";
		}
		const double t1 = now_ns();
		if (step >= static_cast<uint64_t>(o.warmup))
			times.push_back(t1 - t0);
	}
	return {};
}

double percentile(const std::vector<double> &sorted, double p)
{
	size_t i = static_cast<size_t>(p * static_cast<double>(sorted.size() - 1) + 0.5);
	return sorted[std::min(i, sorted.size() - 1)];
}

} // namespace

int main(int argc, char **argv)
{
	Options o;
	if (!parse(argc, argv, o)) {
		std::fprintf(stderr, "usage: dds_barrier [--rounds N] [--domain D] [--signals K] [--spread]\n");
		return 2;
	}
	if (o.domain < 0)
		o.domain = 200 + getpid() % 30;
	// Loopback alone unless the caller configured Cyclone otherwise; set
	// before the fork, so both participants read the same.
	setenv("CYCLONEDDS_URI", loopback_uri, 0);
	// The world id keeps two runs in one domain apart.
	const auto world = static_cast<uint32_t>(getpid());
	const auto last_step = static_cast<uint64_t>(o.warmup + o.rounds - 1);

	if (!o.spread)
		bench_pin_to_last_cpu(); // the agent and every DDS thread inherit it
	std::fflush(stdout);
	const pid_t parent = getpid();
	const pid_t pid = fork();
	if (pid < 0) {
		std::perror("dds_barrier: fork");
		return 1;
	}
	if (pid == 0) {
		// Never outlive the host, even if it dies before the next line.
		if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || getppid() != parent)
			_exit(1);
		Side s;
		std::string err = agent(o, world, last_step, s);
		// Deleting the participant lingers until the host has
		// acknowledged the last StepDone.
		if (s.participant > 0)
			dds_delete(s.participant);
		if (!err.empty()) {
			std::fprintf(stderr, "dds_barrier: agent: %s\n", err.c_str());
			_exit(1);
		}
		_exit(0);
	}

	Side s;
	std::vector<double> times;
	std::string err = host(o, world, last_step, s, times);
	if (!err.empty())
		kill(pid, SIGTERM);
	// The participant stays until the agent has exited, so the agent's
	// last StepDone is acknowledged and its participant's delete returns.
	int status = 0;
	while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
	}
	if (s.participant > 0)
		dds_delete(s.participant);
	if (!err.empty()) {
		std::fprintf(stderr, "dds_barrier: %s\n", err.c_str());
		return 1;
	}
	if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
		std::fprintf(stderr, "dds_barrier: the agent failed\n");
		return 1;
	}
	std::sort(times.begin(), times.end());
	std::printf("rounds=%zu median_us=%.1f p99_us=%.1f min_us=%.1f\n", times.size(), percentile(times, 0.5) / 1e3,
		    percentile(times, 0.99) / 1e3, times.front() / 1e3);
	return 0;
}
