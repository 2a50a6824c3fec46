/* legacy_alarm_pd SECONDS: the oldest control loop there is. A periodic
 * ITIMER_REAL at 1 kHz; the control law (swing the built-in pendulum up and
 * balance it) runs in the SIGALRM handler, which reads the state device and
 * writes the torque device with read(2) and write(2); main only pause()s.
 * Prints the handler's runs, the monotonic times of its first and last run,
 * the largest gap between two runs, and the worst distance from upright
 * over the last 2 s (the test judges the pendulum from the trace too). */
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

static int state_fd, torque_fd;
static volatile long long runs, first_ns = -1, last_ns, max_gap, bad_reads;
static volatile double worst_recent, end_s;
static volatile sig_atomic_t done;

static long long mono_ns(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

static double wrap_pi(double a)
{
	a = fmod(a + M_PI, 2 * M_PI);
	return a < 0 ? a + M_PI : a - M_PI;
}

static double control(double theta, double omega)
{
	const double m = 1.0, l = 1.0, lim = 5.0, g = 9.81, inertia = m * l * l / 3;
	double err = wrap_pi(theta - M_PI);
	double u;
	if (fabs(err) < 0.3 && fabs(omega) < 3.0) {
		u = -40.0 * err - 8.0 * omega;
	} else {
		double energy = 0.5 * inertia * omega * omega + m * g * l / 2 * (1 - cos(theta));
		u = 8.0 * (m * g * l - energy) * (omega >= 0 ? 1 : -1);
	}
	return u > lim ? lim : u < -lim ? -lim : u;
}

/* The control law, as legacy code has it: all of it in the handler. */
static void on_alarm(int sig)
{
	(void)sig;
	long long now = mono_ns();
	if (first_ns < 0)
		first_ns = now;
	else if (now - last_ns > max_gap)
		max_gap = now - last_ns;
	last_ns = now;
	runs++;
	char line[128];
	ssize_t n = read(state_fd, line, sizeof line - 1);
	if (n <= 0) {
		bad_reads++;
		return;
	}
	line[n] = '\0';
	char *end;
	double theta = strtod(line, &end), omega = strtod(end, NULL);
	double err = fabs(wrap_pi(theta - M_PI));
	if ((now - first_ns) / 1e9 > end_s - 2 && err > worst_recent)
		worst_recent = err;
	char out[64];
	int len = snprintf(out, sizeof out, "%.6f\n", control(theta, omega));
	if (write(torque_fd, out, (size_t)len) != len)
		bad_reads++;
	if ((now - first_ns) / 1e9 >= end_s)
		done = 1;
}

int main(int argc, char **argv)
{
	end_s = argc > 1 ? atof(argv[1]) : 5;
	state_fd = open("/dev/tcs/pendulum/state", O_RDONLY);
	torque_fd = open("/dev/tcs/pendulum/torque", O_WRONLY);
	if (state_fd < 0 || torque_fd < 0) {
		perror("legacy_alarm_pd: open");
		return 1;
	}
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_alarm;
	sigaction(SIGALRM, &sa, NULL);
	struct itimerval every_ms = { { 0, 1000 }, { 0, 1000 } };
	setitimer(ITIMER_REAL, &every_ms, NULL);
	while (!done)
		pause();
	struct itimerval off = { { 0, 0 }, { 0, 0 } };
	setitimer(ITIMER_REAL, &off, NULL);
	printf("runs=%lld\nfirst_ns=%lld\nlast_ns=%lld\nmax_gap_ns=%lld\nbad_reads=%lld\nworst_last2s=%.6f\n", runs,
	       first_ns, last_ns, max_gap, bad_reads, worst_recent);
	return 0;
}
