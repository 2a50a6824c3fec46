// pendulum_pd_cpp: swing a pendulum up and balance it, at 1 kHz, as a plain
// C++ program that knows nothing of tcs. It reads "position velocity" lines
// from the state device, writes a torque line to the torque device, and
// paces itself with std::this_thread::sleep_until on std::chrono::steady_clock
// — on hardware the two paths would be the drivers of a real encoder and
// motor. The same controller as pendulum_pd.c, written the way a C++
// robotics program would be.
//
// Control: energy pumping (the rod's energy driven towards that of the
// upright rest, torque in the direction of motion, within the motor's
// limit) until the pendulum comes near the top, then a PD law about the
// upright. Angle 0 hangs down, pi is up; positive torque raises the angle.
//
//   pendulum_pd_cpp [--rate HZ] [--seconds S] [--work-us N]
//                   [--state PATH] [--torque PATH] [--length L] [--mass M]
//                   [--limit N*m]
//
// --work-us N burns N microseconds of this machine's CPU every cycle,
// standing for a heavier control law; a target CPU --cpu-scale times slower
// takes that many times longer for the same work. At the end it prints how
// it did: the largest distance from upright over its last 2 seconds.
#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>

#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

namespace {

volatile std::sig_atomic_t stop;

extern "C" void on_signal(int)
{
	stop = 1;
}

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0)
{
	return std::chrono::duration<double>(Clock::now() - t0).count();
}

// ---- the stand-in for a heavier control law --------------------------------

volatile unsigned long long sink;

void rounds(unsigned long long n)
{
	unsigned long long x = sink + 88172645463325252ull;
	for (unsigned long long i = 0; i < n; i++) {
		x ^= x << 13;
		x ^= x >> 7;
		x ^= x << 17;
	}
	sink = x;
}

// This machine's real CPU time. The raw system call is deliberate: it is
// the one clock a simulator leaves alone, so --work-us means microseconds
// of *this* CPU, and a slower target CPU (tcs-run --cpu-scale) takes longer
// for the same work, as it would on the robot.
double real_cpu_s()
{
	struct timespec ts {};
	syscall(SYS_clock_gettime, CLOCK_THREAD_CPUTIME_ID, &ts);
	return ts.tv_sec + ts.tv_nsec / 1e9;
}

// Rounds per microsecond of this CPU: the fastest of five rounds of about
// 5 ms. On a shared machine a round can run slow (a busy neighbour core),
// and one slow round alone would make every cycle's work short by as much.
// Short, about 30 ms in all, since the world runs meanwhile.
double rounds_per_us()
{
	unsigned long long n = 1000;
	double dt;
	for (;;) {
		double t0 = real_cpu_s();
		rounds(n);
		dt = real_cpu_s() - t0;
		if (dt >= 0.001)
			break;
		n *= 2;
	}
	n = static_cast<unsigned long long>(n * 0.005 / dt) + 1;
	double best = 0;
	for (int i = 0; i < 5; i++) {
		double t0 = real_cpu_s();
		rounds(n);
		dt = real_cpu_s() - t0;
		if (dt > 0)
			best = std::max(best, n / (dt * 1e6));
	}
	return best;
}

// ---- control ----------------------------------------------------------------

constexpr double pi = std::numbers::pi;

struct Params {
	double mass = 1.0, length = 1.0, limit = 5.0;
};

double wrap_pi(double a)
{
	a = std::fmod(a + pi, 2 * pi);
	return a < 0 ? a + pi : a - pi;
}

double clamp(double v, double lim)
{
	return v > lim ? lim : v < -lim ? -lim : v;
}

double control(const Params &p, double theta, double omega)
{
	const double g = 9.81, inertia = p.mass * p.length * p.length / 3;
	double err = wrap_pi(theta - pi); // 0 when upright
	if (std::fabs(err) < 0.3 && std::fabs(omega) < 3.0)
		return clamp(-40.0 * err - 8.0 * omega, p.limit);
	double energy = 0.5 * inertia * omega * omega + p.mass * g * p.length / 2 * (1 - std::cos(theta));
	double target = p.mass * g * p.length;
	double push = omega == 0 ? 1 : omega > 0 ? 1 : -1;
	return clamp(8.0 * (target - energy) * push, p.limit);
}

void usage(const char *argv0, std::FILE *out)
{
	std::fprintf(out,
		     "usage: %s [--rate HZ] [--seconds S] [--work-us N] [--state PATH] [--torque PATH]"
		     " [--length L] [--mass M] [--limit N*m]\n",
		     argv0);
}

bool parse_number(const std::string &s, double &out)
{
	char *end = nullptr;
	errno = 0;
	out = std::strtod(s.c_str(), &end);
	return !s.empty() && end && *end == '\0' && errno == 0;
}

} // namespace

int main(int argc, char **argv)
{
	double rate = 1000, seconds = 0, work_us = 0;
	Params p;
	std::string state_path = "/dev/tcs/pendulum/state", torque_path = "/dev/tcs/pendulum/torque";

	// A small parser: --name VALUE, --name=VALUE, and -r/-s/-w VALUE (or -rVALUE).
	for (int i = 1; i < argc; i++) {
		std::string_view arg = argv[i];
		if (arg == "--help" || arg == "-h") {
			usage(argv[0], stdout);
			return 0;
		}
		std::string name(arg), value;
		bool have_value = false;
		if (auto eq = arg.find('='); arg.starts_with("--") && eq != std::string_view::npos) {
			name = std::string(arg.substr(0, eq));
			value = std::string(arg.substr(eq + 1));
			have_value = true;
		}
		if (name.size() > 2 && name[0] == '-' && name[1] != '-' && !have_value) {
			value = name.substr(2); // -r500, as getopt allows
			name = name.substr(0, 2);
			have_value = true;
		}
		if (name == "-r")
			name = "--rate";
		else if (name == "-s")
			name = "--seconds";
		else if (name == "-w")
			name = "--work-us";
		static constexpr std::string_view known[] = { "--rate",	  "--seconds", "--work-us", "--state",
							      "--torque", "--length",  "--mass",    "--limit" };
		bool is_known = false;
		for (auto k : known)
			is_known = is_known || name == k;
		if (!is_known) {
			std::fprintf(stderr, "%s: unknown option '%s'\n", argv[0], argv[i]);
			usage(argv[0], stderr);
			return 2;
		}
		if (!have_value) {
			if (i + 1 >= argc) {
				std::fprintf(stderr, "%s: option '%s' requires an argument\n", argv[0], name.c_str());
				usage(argv[0], stderr);
				return 2;
			}
			value = argv[++i];
		}
		if (name == "--state") {
			state_path = value;
			continue;
		}
		if (name == "--torque") {
			torque_path = value;
			continue;
		}
		double v;
		if (!parse_number(value, v)) {
			std::fprintf(stderr, "%s: option '%s': not a number: '%s'\n", argv[0], name.c_str(), value.c_str());
			return 2;
		}
		if (name == "--rate")
			rate = v;
		else if (name == "--seconds")
			seconds = v;
		else if (name == "--work-us")
			work_us = v;
		else if (name == "--length")
			p.length = v;
		else if (name == "--mass")
			p.mass = v;
		else
			p.limit = v;
	}
	if (!(rate > 0) || work_us < 0) {
		std::fprintf(stderr, "%s: --rate must be positive and --work-us not negative\n", argv[0]);
		return 2;
	}

	std::ifstream state(state_path);
	if (!state) {
		std::fprintf(stderr, "%s: cannot open %s: %s\n", argv[0], state_path.c_str(), std::strerror(errno));
		return 1;
	}
	std::ofstream torque(torque_path);
	if (!torque) {
		std::fprintf(stderr, "%s: cannot open %s: %s\n", argv[0], torque_path.c_str(), std::strerror(errno));
		return 1;
	}
	std::signal(SIGTERM, on_signal);
	std::signal(SIGINT, on_signal);
	auto work = static_cast<unsigned long long>(work_us * (work_us > 0 ? rounds_per_us() : 0));
	torque.setf(std::ios::fixed);
	torque.precision(6);

	const auto period = std::chrono::nanoseconds(static_cast<long long>(1e9 / rate));
	auto next = Clock::now();
	const auto start = Clock::now();
	double worst_recent = 0, theta = 0, omega = 0;
	long long cycles = 0, misses = 0;
	std::string line;
	while (!stop && (seconds <= 0 || seconds_since(start) < seconds)) {
		if (!std::getline(state, line)) {
			std::fprintf(stderr, "%s: bad state record\n", argv[0]);
			return 1;
		}
		std::istringstream fields(line);
		if (!(fields >> theta >> omega)) {
			std::fprintf(stderr, "%s: bad state record\n", argv[0]);
			return 1;
		}
		rounds(work);
		torque << control(p, theta, omega) << '\n' << std::flush;
		cycles++;
		// How upright it is over the last 2 s of the run.
		double err = std::fabs(wrap_pi(theta - pi));
		if (seconds > 0 && seconds_since(start) > seconds - 2 && err > worst_recent)
			worst_recent = err;

		next += period;
		if (Clock::now() > next)
			misses++;
		std::this_thread::sleep_until(next);
	}
	double elapsed = seconds_since(start);
	int balanced = seconds > 0 && worst_recent < 0.1;
	std::printf("pendulum_pd: %lld cycles in %.3f s (%.1f Hz), %lld deadline misses, final angle %.3f rad, "
		    "worst distance from upright over the last 2 s %.3f rad: %s\n",
		    cycles, elapsed, cycles / elapsed, misses, theta, worst_recent, balanced ? "BALANCED" : "FELL");
	std::printf("cycles=%lld rate_hz=%.3f misses=%lld worst_last2s=%.6f balanced=%d\n", cycles, cycles / elapsed,
		    misses, worst_recent, balanced);
	return 0;
}
