/* acrobot_swingup: swing an acrobot up from hanging and balance it on its
 * end, as a plain C program that knows nothing of tcs. The robot is
 * examples/acrobot/acrobot.urdf: a passive shoulder and a driven elbow,
 * angles 0 hanging down, about the joints' +y axes.
 *
 * It reads "q1 q2 dq1 dq2" lines (rad, rad/s) from the state device and
 * writes an elbow torque line (N*m) to the torque device each cycle, paced
 * by clock_nanosleep(TIMER_ABSTIME).
 *
 * Control: far from the top, energy pumping through the elbow (its power
 * kept positive while the energy falls short of the upright rest's, as in
 * Spong's swing-up, 1995); near the top, a linear quadratic regulator of
 * the model linearised there, computed at start-up (its Riccati equation
 * iterated), which takes over once its cost-to-go is small.
 *
 *   acrobot_swingup [--rate HZ] [--seconds S] [--state PATH] [--torque PATH]
 *                   [--limit N*m] [--work-us N]
 *
 * At the end it prints how it did: when it first came within 0.1 rad of
 * upright, and the largest distance from upright over its last second. */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* The model, as the URDF gives it. */
static const double m1 = 1, m2 = 1, l1 = 1, lc1 = 0.5, lc2 = 1, Ic1 = 0.083, Ic2 = 0.33, b = 0.1, g = 9.81;

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

static double wrap_pi(double a)
{
	a = fmod(a + M_PI, 2 * M_PI);
	return a < 0 ? a + M_PI : a - M_PI;
}

static double clamp(double v, double lim)
{
	return v > lim ? lim : v < -lim ? -lim : v;
}

/* The equations of motion M(q) qdd = h(q, qd) + (0, u). */
struct dyn {
	double M11, M12, M22, h1, h2;
};

static struct dyn dynamics(const double x[4])
{
	const double I1 = Ic1 + m1 * lc1 * lc1, I2 = Ic2 + m2 * lc2 * lc2;
	const double c2 = cos(x[1]), s2 = sin(x[1]), s1 = sin(x[0]), s12 = sin(x[0] + x[1]);
	struct dyn d;
	d.M11 = I1 + I2 + m2 * l1 * l1 + 2 * m2 * l1 * lc2 * c2;
	d.M12 = I2 + m2 * l1 * lc2 * c2;
	d.M22 = I2;
	const double k = m2 * l1 * lc2 * s2;
	d.h1 = 2 * k * x[2] * x[3] + k * x[3] * x[3] - m1 * g * lc1 * s1 - m2 * g * (l1 * s1 + lc2 * s12) - b * x[2];
	d.h2 = -k * x[2] * x[2] - m2 * g * lc2 * s12 - b * x[3];
	return d;
}

/* The state's derivative under torque u. */
static void derivative(const double x[4], double u, double dx[4])
{
	struct dyn d = dynamics(x);
	const double det = d.M11 * d.M22 - d.M12 * d.M12;
	dx[0] = x[2];
	dx[1] = x[3];
	dx[2] = (d.M22 * d.h1 - d.M12 * (d.h2 + u)) / det;
	dx[3] = (-d.M12 * d.h1 + d.M11 * (d.h2 + u)) / det;
}

static double energy(const double x[4])
{
	struct dyn d = dynamics(x);
	const double kinetic = 0.5 * (d.M11 * x[2] * x[2] + 2 * d.M12 * x[2] * x[3] + d.M22 * x[3] * x[3]);
	const double potential = -m1 * g * lc1 * cos(x[0]) - m2 * g * (l1 * cos(x[0]) + lc2 * cos(x[0] + x[1]));
	return kinetic + potential;
}

/* ---- the balancing regulator ------------------------------------------------ */

static double K[4]; /* u = -K (x - upright) */
static double P[4][4];

/* The model linearised at the upright rest by central differences, made
 * discrete at the control period, and its Riccati equation iterated to a
 * fixed point: the regulator's gain and cost-to-go. */
static void design_lqr(double dt)
{
	const double up[4] = { M_PI, 0, 0, 0 }, h = 1e-6;
	double A[4][4], B[4];
	for (int j = 0; j < 4; j++) {
		double xp[4], xm[4], dp[4], dm[4];
		memcpy(xp, up, sizeof xp);
		memcpy(xm, up, sizeof xm);
		xp[j] += h;
		xm[j] -= h;
		derivative(xp, 0, dp);
		derivative(xm, 0, dm);
		for (int i = 0; i < 4; i++)
			A[i][j] = (i == j ? 1 : 0) + dt * (dp[i] - dm[i]) / (2 * h);
	}
	double dp[4], dm[4];
	derivative(up, h, dp);
	derivative(up, -h, dm);
	for (int i = 0; i < 4; i++)
		B[i] = dt * (dp[i] - dm[i]) / (2 * h);
	const double Q[4] = { 10, 10, 1, 1 }, R = 1;
	memset(P, 0, sizeof P);
	for (int i = 0; i < 4; i++)
		P[i][i] = Q[i];
	/* P = Q + F'PF + K'RK with F = A - BK: the form that stays positive
	 * definite in floating point (the textbook one loses it here: the
	 * acrobot is barely controllable at the top, and it diverged). */
	for (int iter = 0; iter < 100000; iter++) {
		double PB[4], BPB = R, F[4][4], next[4][4], change = 0, scale = 1;
		for (int i = 0; i < 4; i++) {
			PB[i] = 0;
			for (int j = 0; j < 4; j++)
				PB[i] += P[i][j] * B[j];
			BPB += B[i] * PB[i];
		}
		for (int j = 0; j < 4; j++) {
			double bpa = 0; /* (B'PA)_j */
			for (int i = 0; i < 4; i++)
				bpa += PB[i] * A[i][j];
			K[j] = bpa / BPB;
		}
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				F[i][j] = A[i][j] - B[i] * K[j];
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++) {
				double fpf = 0;
				for (int k = 0; k < 4; k++)
					for (int l = 0; l < 4; l++)
						fpf += F[k][i] * P[k][l] * F[l][j];
				next[i][j] = (i == j ? Q[i] : 0) + fpf + R * K[i] * K[j];
				change = fmax(change, fabs(next[i][j] - P[i][j]));
				scale = fmax(scale, fabs(next[i][j]));
			}
		memcpy(P, next, sizeof P);
		if (change < 1e-10 * scale)
			break;
	}
	/* The cost-to-go per second, as the continuous regulator's. */
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			P[i][j] *= dt;
}

static double cost_to_go(const double e[4])
{
	double c = 0;
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			c += e[i] * P[i][j] * e[j];
	return c;
}

/* ---- the law ---------------------------------------------------------------- */

static double control(const double x[4], double limit)
{
	const double e[4] = { wrap_pi(x[0] - M_PI), wrap_pi(x[1]), x[2], x[3] };
	if (cost_to_go(e) < 1000)
		return clamp(-(K[0] * e[0] + K[1] * e[1] + K[2] * e[2] + K[3] * e[3]), limit);
	/* Energy pumping: the elbow's power q2' u is made positive while the
	 * energy falls short of the upright rest's (u along q2', in proportion
	 * to the shortfall), and a spring keeps the elbow near straight. At
	 * rest at the bottom nothing moves: a nudge starts it. */
	const double upright[4] = { M_PI, 0, 0, 0 };
	const double shortfall = energy(x) - energy(upright);
	if (fabs(x[2]) + fabs(x[3]) < 0.05 && shortfall < -1)
		return limit / 4;
	return clamp(-2 * shortfall * x[3] - 10 * wrap_pi(x[1]), limit);
}

int main(int argc, char **argv)
{
	double rate = 500, seconds = 0, limit = 20;
	const char *state_path = "/dev/tcs/acrobot/state", *torque_path = "/dev/tcs/acrobot/torque";
	static const struct option opts[] = {
		{ "rate", required_argument, NULL, 'r' },  { "seconds", required_argument, NULL, 's' },
		{ "state", required_argument, NULL, 'i' }, { "torque", required_argument, NULL, 'o' },
		{ "limit", required_argument, NULL, 'u' }, { "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	int c;
	while ((c = getopt_long(argc, argv, "r:s:h", opts, NULL)) != -1) {
		switch (c) {
		case 'r': rate = atof(optarg); break;
		case 's': seconds = atof(optarg); break;
		case 'i': state_path = optarg; break;
		case 'o': torque_path = optarg; break;
		case 'u': limit = atof(optarg); break;
		default:
			fprintf(stderr, "usage: %s [--rate HZ] [--seconds S] [--state PATH] [--torque PATH] [--limit N*m]\n",
				argv[0]);
			return c == 'h' ? 0 : 2;
		}
	}
	if (!(rate > 0 && rate <= 100000) || !(limit > 0)) {
		fprintf(stderr, "%s: --rate must be in (0, 100000] and --limit positive\n", argv[0]);
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
	design_lqr(1.0 / rate);

	const long long period = (long long)(1e9 / rate);
	struct timespec next;
	clock_gettime(CLOCK_MONOTONIC, &next);
	double start = now_s(), worst_recent = 0, reached = -1, x[4];
	/* How far from upright each cycle of the last second was. */
	const long long window = (long long)ceil(rate);
	double *recent = calloc((size_t)window, sizeof *recent);
	if (!recent) {
		fprintf(stderr, "%s: out of memory\n", argv[0]);
		return 1;
	}
	long long cycles = 0;
	char line[256];
	while (!stop && (seconds <= 0 || now_s() - start < seconds)) {
		if (!fgets(line, sizeof line, state) || sscanf(line, "%lf %lf %lf %lf", &x[0], &x[1], &x[2], &x[3]) != 4) {
			fprintf(stderr, "%s: bad state record\n", argv[0]);
			return 1;
		}
		fprintf(torque, "%.6f\n", control(x, limit));
		fflush(torque);
		cycles++;
		const double off = fmax(fabs(wrap_pi(x[0] - M_PI)), fabs(wrap_pi(x[0] + x[1] - M_PI)));
		if (reached < 0 && off < 0.1)
			reached = now_s() - start;
		recent[cycles % window] = off;
		next.tv_nsec += period;
		while (next.tv_nsec >= 1000000000L) {
			next.tv_nsec -= 1000000000L;
			next.tv_sec++;
		}
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL);
	}
	/* The last second's cycles (all of them, if it ran less). */
	for (long long i = 0; i < cycles && i < window; i++)
		worst_recent = fmax(worst_recent, recent[i]);
	free(recent);
	printf("cycles=%lld upright_at=%.3f worst_last_second=%.4f\n", cycles, reached, worst_recent);
	return 0;
}
