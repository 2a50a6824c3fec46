/* pendulum_pd: swing a pendulum up and balance it, at 1 kHz, as a plain C
 * program that knows nothing of tcs. It reads "position velocity" lines
 * from the state device, writes a torque line to the torque device, and
 * paces itself with clock_nanosleep(TIMER_ABSTIME) — on hardware the two
 * paths would be the drivers of a real encoder and motor.
 *
 * Control: energy pumping (the rod's energy driven towards that of the
 * upright rest, torque in the direction of motion, within the motor's
 * limit) until the pendulum comes near the top, then a PD law about the
 * upright. Angle 0 hangs down, pi is up; positive torque raises the angle.
 *
 *   pendulum_pd [--rate HZ] [--seconds S] [--work-us N]
 *               [--state PATH] [--torque PATH] [--length L] [--mass M]
 *
 * --work-us N burns N microseconds of this machine's CPU every cycle,
 * standing for a heavier control law; a target CPU --cpu-scale times slower
 * takes that many times longer for the same work. At the end it prints how
 * it did: the largest distance from upright over its last 2 seconds. */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

static volatile sig_atomic_t stop;

static void on_signal(int sig)
{
	(void)sig;
	stop = 1;
}

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return ts.tv_sec + ts.tv_nsec / 1e9;
}

/* ---- the stand-in for a heavier control law ------------------------------- */

static volatile unsigned long long sink;

static void rounds(unsigned long long n)
{
	unsigned long long x = sink + 88172645463325252ull;
	for (unsigned long long i = 0; i < n; i++) {
		x ^= x << 13;
		x ^= x >> 7;
		x ^= x << 17;
	}
	sink = x;
}

/* This machine's real CPU time. The raw system call is deliberate: it is
 * the one clock a simulator leaves alone, so --work-us means microseconds
 * of *this* CPU, and a slower target CPU (tcs-run --cpu-scale) takes longer
 * for the same work, as it would on the robot. */
static double real_cpu_s(void)
{
	struct timespec ts;
	syscall(SYS_clock_gettime, CLOCK_THREAD_CPUTIME_ID, &ts);
	return ts.tv_sec + ts.tv_nsec / 1e9;
}

/* Rounds per microsecond of this CPU: the fastest of five rounds of about
 * 5 ms. On a shared machine a round can run slow (a busy neighbour core),
 * and one slow round alone would make every cycle's work short by as much.
 * Short, about 30 ms in all, since the world runs meanwhile. */
static double rounds_per_us(void)
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
	n = (unsigned long long)(n * 0.005 / dt) + 1;
	double best = 0;
	for (int i = 0; i < 5; i++) {
		double t0 = real_cpu_s();
		rounds(n);
		dt = real_cpu_s() - t0;
		if (dt > 0 && n / (dt * 1e6) > best)
			best = n / (dt * 1e6);
	}
	return best;
}

/* ---- control ------------------------------------------------------------ */

struct params {
	double mass, length, limit;
};

static double wrap_pi(double a)
{
	a = fmod(a + M_PI, 2 * M_PI);
	return a < 0 ? a + M_PI : a - M_PI;
}

static double clamp(double v, double lim)
{
	return v > lim ? lim : v < -lim ? -lim : v;
}

static double control(const struct params *p, double theta, double omega)
{
	const double g = 9.81, inertia = p->mass * p->length * p->length / 3;
	double err = wrap_pi(theta - M_PI); /* 0 when upright */
	if (fabs(err) < 0.3 && fabs(omega) < 3.0)
		return clamp(-40.0 * err - 8.0 * omega, p->limit);
	double energy = 0.5 * inertia * omega * omega + p->mass * g * p->length / 2 * (1 - cos(theta));
	double target = p->mass * g * p->length;
	double push = omega == 0 ? 1 : omega > 0 ? 1 : -1;
	return clamp(8.0 * (target - energy) * push, p->limit);
}

int main(int argc, char **argv)
{
	double rate = 1000, seconds = 0, work_us = 0;
	struct params p = { 1.0, 1.0, 5.0 };
	const char *state_path = "/dev/tcs/pendulum/state", *torque_path = "/dev/tcs/pendulum/torque";
	static const struct option opts[] = {
		{ "rate", required_argument, NULL, 'r' },   { "seconds", required_argument, NULL, 's' },
		{ "work-us", required_argument, NULL, 'w' }, { "state", required_argument, NULL, 'i' },
		{ "torque", required_argument, NULL, 'o' },  { "length", required_argument, NULL, 'l' },
		{ "mass", required_argument, NULL, 'm' },    { "limit", required_argument, NULL, 'u' },
		{ "help", no_argument, NULL, 'h' },          { NULL, 0, NULL, 0 },
	};
	int c;
	while ((c = getopt_long(argc, argv, "r:s:w:h", opts, NULL)) != -1) {
		switch (c) {
		case 'r': rate = atof(optarg); break;
		case 's': seconds = atof(optarg); break;
		case 'w': work_us = atof(optarg); break;
		case 'i': state_path = optarg; break;
		case 'o': torque_path = optarg; break;
		case 'l': p.length = atof(optarg); break;
		case 'm': p.mass = atof(optarg); break;
		case 'u': p.limit = atof(optarg); break;
		default:
			fprintf(stderr, "usage: %s [--rate HZ] [--seconds S] [--work-us N] [--state PATH] [--torque PATH]"
					" [--length L] [--mass M] [--limit N*m]\n", argv[0]);
			return c == 'h' ? 0 : 2;
		}
	}
	if (rate <= 0 || work_us < 0) {
		fprintf(stderr, "%s: --rate must be positive and --work-us not negative\n", argv[0]);
		return 2;
	}
	FILE *state = fopen(state_path, "r");
	FILE *torque = fopen(torque_path, "w");
	if (!state || !torque) {
		fprintf(stderr, "%s: cannot open %s: %s\n", argv[0], state ? torque_path : state_path, strerror(errno));
		return 1;
	}
	signal(SIGTERM, on_signal);
	signal(SIGINT, on_signal);
	unsigned long long work = (unsigned long long)(work_us * (work_us > 0 ? rounds_per_us() : 0));

	const long long period = (long long)(1e9 / rate);
	struct timespec next;
	clock_gettime(CLOCK_MONOTONIC, &next);
	double start = now_s(), worst_recent = 0, theta = 0, omega = 0, last_far = start;
	long long cycles = 0, misses = 0;
	char line[256];
	while (!stop && (seconds <= 0 || now_s() - start < seconds)) {
		if (!fgets(line, sizeof line, state) || sscanf(line, "%lf %lf", &theta, &omega) != 2) {
			fprintf(stderr, "%s: bad state record\n", argv[0]);
			return 1;
		}
		rounds(work);
		fprintf(torque, "%.6f\n", control(&p, theta, omega));
		fflush(torque);
		cycles++;
		/* How upright it is over the last 2 s of the run. */
		double err = fabs(wrap_pi(theta - M_PI));
		if (seconds > 0 && now_s() - start > seconds - 2 && err > worst_recent)
			worst_recent = err;
		if (err >= 0.1)
			last_far = now_s();

		next.tv_nsec += period;
		while (next.tv_nsec >= 1000000000L) {
			next.tv_nsec -= 1000000000L;
			next.tv_sec++;
		}
		struct timespec t;
		clock_gettime(CLOCK_MONOTONIC, &t);
		if (t.tv_sec > next.tv_sec || (t.tv_sec == next.tv_sec && t.tv_nsec > next.tv_nsec))
			misses++;
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL);
	}
	double elapsed = now_s() - start;
	/* Balanced: within 0.1 rad of upright for (at least) its last 2 s. */
	int balanced = seconds > 0 ? worst_recent < 0.1 : now_s() - last_far >= 2;
	printf("pendulum_pd: %lld cycles in %.3f s (%.1f Hz), %lld deadline misses, final angle %.3f rad, "
	       "worst distance from upright over the last 2 s %.3f rad: %s\n",
	       cycles, elapsed, cycles / elapsed, misses, theta, worst_recent, balanced ? "BALANCED" : "FELL");
	printf("cycles=%lld rate_hz=%.3f misses=%lld worst_last2s=%.6f balanced=%d\n", cycles, cycles / elapsed, misses,
	       worst_recent, balanced);
	return 0;
}
