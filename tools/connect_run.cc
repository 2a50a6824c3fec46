// run_connected(): one controller under coordinatord, start to end.
#include "connect_run.h"

#include <poll.h>
#include <signal.h>
#include <sys/signalfd.h>
#include <time.h>
#include <unistd.h>

#include <cstdio>

#include "attach_protocol.h"
#include "attach_socket.h"
#include "run_report.h"
#include "tcs/protocol.h"

extern char **environ;

namespace tcs {

namespace {

int64_t now_ns()
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return tcs_ts_to_ns(&ts);
}

std::string absolute(const std::string &path)
{
	if (!path.empty() && path[0] == '/')
		return path;
	char cwd[4096];
	return getcwd(cwd, sizeof cwd) ? std::string(cwd) + "/" + path : path;
}

// What the daemon reported, as tcs-run's own summary says it.
std::string summary_of(const ConnectRequest &req, const StartedReply &s, const EndedReply &e, int64_t wall_ns)
{
	RunReport r;
	r.virtual_ns = e.v_end - s.v_start;
	r.wall_ns = wall_ns;
	r.realtime.fifo = s.fifo_cpu >= 0;
	r.realtime.cpu = s.fifo_cpu;
	ControllerReport c;
	c.id = s.id;
	c.pid = s.pid;
	c.name = req.argv[0];
	c.wait_status = e.wait_status;
	c.ended_by_tcs = e.flags & kEndedByTcs;
	c.attached = e.flags & kEndedAttached;
	c.dropped = e.dropped;
	c.virtual_ns = e.v_end - s.v_start;
	c.charged_ns = e.charged_ns;
	c.waits = e.waits;
	c.periodic_waits = e.periodic_waits;
	c.deadline_misses = e.deadline_misses;
	c.preemptions = e.preemptions;
	r.controllers.push_back(c);
	return summary(r, s.mode);
}

} // namespace

Result<int> run_connected(const ConnectRequest &req)
{
	auto fd = connect_socket(req.socket);
	if (!fd)
		return fd.error();
	RunRequest run;
	run.path = absolute(req.path);
	run.cwd = absolute(".");
	run.argv = req.argv;
	for (char **e = environ; e && *e; e++)
		run.env.push_back(*e);
	run.cpu_scale = req.cpu_scale;
	// Signals are passed on from here on, not acted on.
	sigset_t mask;
	sigemptyset(&mask);
	for (int s : { SIGINT, SIGTERM, SIGHUP, SIGQUIT })
		sigaddset(&mask, s);
	sigprocmask(SIG_BLOCK, &mask, nullptr);
	int sfd = signalfd(-1, &mask, SFD_CLOEXEC);
	if (sfd < 0)
		return errno_error("signalfd");
	UniqueFd signals(sfd);
	if (auto s = send_frame(fd->get(), encode_frame(AttachType::Run, encode_run(run)), { 0, 1, 2 }); !s)
		return Error{ req.socket + ": " + s.error().message };

	const int64_t wall_start = now_ns();
	std::string in;
	std::vector<UniqueFd> no_fds;
	StartedReply started;
	bool running = false;
	int signals_seen = 0;
	for (;;) {
		struct pollfd p[2] = { { fd->get(), POLLIN, 0 }, { signals.get(), POLLIN, 0 } };
		if (poll(p, 2, -1) < 0) {
			if (errno == EINTR)
				continue;
			return errno_error("poll");
		}
		if (p[1].revents & POLLIN) {
			struct signalfd_siginfo si;
			if (read(signals.get(), &si, sizeof si) == (ssize_t)sizeof si) {
				// Once as sent; asked again, no more grace.
				int32_t signo = signals_seen++ == 0 ? (int32_t)si.ssi_signo : SIGKILL;
				(void)send_frame(fd->get(), encode_frame(AttachType::Signal, encode_signal(signo)));
			}
		}
		if (!(p[0].revents & (POLLIN | POLLHUP | POLLERR)))
			continue;
		ssize_t n = recv_some(fd->get(), in, no_fds, 0);
		if (n < 0 && (errno == EAGAIN || errno == EINTR))
			continue;
		if (n <= 0)
			return Error{ "coordinatord at " + req.socket + " went away before " + req.argv[0] + " ended" };
		for (;;) {
			auto f = take_frame(in);
			if (!f)
				return Error{ req.socket + ": " + f.error().message };
			if (!*f)
				break;
			const AttachFrame &frame = **f;
			if (frame.type == AttachType::Refused)
				return Error{ "coordinatord refused: " + frame.payload };
			if (frame.type == AttachType::Started && !running) {
				auto s = decode_started(frame.payload);
				if (!s)
					return Error{ req.socket + ": " + s.error().message };
				started = *s;
				running = true;
				continue;
			}
			if (frame.type == AttachType::Ended && running) {
				auto e = decode_ended(frame.payload);
				if (!e)
					return Error{ req.socket + ": " + e.error().message };
				if (!req.quiet)
					fputs(summary_of(req, started, *e, now_ns() - wall_start).c_str(), stderr);
				if (!e->dropped.empty())
					return 2;
				return e->wait_status < 0 ? 0 : status_code(e->wait_status);
			}
			return Error{ req.socket + ": an unexpected reply from coordinatord" };
		}
	}
}

} // namespace tcs
