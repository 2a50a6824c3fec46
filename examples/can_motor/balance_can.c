/* balance_can: keep an inverted pendulum upright through an MIT-protocol
 * motor (a T-Motor AK or CubeMars drive, as the MIT mini cheetah's
 * firmware speaks) on a SocketCAN interface, as a plain C program that
 * knows nothing of tcs. Raw SocketCAN only: a CAN_RAW socket bound to the
 * interface, struct can_frame written and read; no library.
 *
 * It puts the motor in motor mode, then at a fixed rate (absolute
 * clock_nanosleep deadlines, 500 Hz by default) computes a PD law about
 * upright from the motor's last reply, sends it as a torque command (kp =
 * kd = 0, the law's torque as the feed-forward) and waits for the reply
 * that command brings: the newest position and velocity, for the next
 * cycle. Angle 0 hangs down, pi is up; positive torque raises the angle.
 *
 *   balance_can [--rate HZ] [--seconds S] [--work-us N] [--interface NAME]
 *               [--id N] [--reply-id N] [--torque-range NM] [--motor-pd]
 *
 * --work-us N burns N microseconds of this machine's CPU every cycle,
 * standing for a heavier control law; a target CPU --cpu-scale times
 * slower takes that many times longer for the same work. --motor-pd
 * hands the PD law to the motor (kp, kd and p_des = pi in the command),
 * whose drive applies it at its own rate whatever this loop's.
 *
 * --torque-range and the fixed ranges below must be the motor's (the
 * scenario's [[can.motor]]): the protocol carries raw integers on them.
 * At the end it prints one verdict line, then the same as key=value. */
#include <errno.h>
#include <getopt.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <math.h>
#include <net/if.h>
#include <poll.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

/* The MIT protocol's ranges: the firmware's defaults, and the scenario's. */
#define P_RANGE 12.5  /* rad, +- */
#define V_RANGE 50.0  /* rad/s, +- */
#define KP_MAX 500.0  /* N*m/rad */
#define KD_MAX 5.0    /* N*m*s/rad */
/* The PD law about upright: with the rod's inertia (1/3 kg m^2) and its
 * weight's 4.9 N*m/rad of pull near the top, a closed loop of about
 * 10 rad/s, a little more than critically damped. */
#define KP 40.0
#define KD 8.0

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

/* n rounds of a xorshift: work the compiler cannot drop or shorten. */
static void burn(unsigned long long n)
{
	unsigned long long x = sink + 0x9E3779B97F4A7C15ull;
	for (unsigned long long i = 0; i < n; i++) {
		x ^= x << 13;
		x ^= x >> 7;
		x ^= x << 17;
	}
	sink = x;
}

/* This machine's real CPU time, by the raw system call: the clock a
 * simulator leaves alone, so that --work-us counts microseconds of this
 * CPU, and a slower target (tcs-run --cpu-scale) takes longer for it. */
static double real_cpu_s(void)
{
	struct timespec ts;
	syscall(SYS_clock_gettime, CLOCK_THREAD_CPUTIME_ID, &ts);
	return ts.tv_sec + ts.tv_nsec / 1e9;
}

/* Rounds per microsecond: the best of five tries of about 5 ms each, so
 * that one try slowed by a busy neighbour does not shorten every cycle's
 * work. Each try is long against the clock's own cost (0.2 to 1.4 us a
 * read), so that cost does not count. */
static double rounds_per_us(void)
{
	unsigned long long n = 1000;
	double dt;
	for (;;) {
		double t0 = real_cpu_s();
		burn(n);
		dt = real_cpu_s() - t0;
		if (dt >= 0.001)
			break;
		n *= 2;
	}
	n = (unsigned long long)(n * 0.005 / dt) + 1;
	double best = 0;
	for (int i = 0; i < 5; i++) {
		double t0 = real_cpu_s();
		burn(n);
		dt = real_cpu_s() - t0;
		if (dt > 0 && n / (dt * 1e6) > best)
			best = n / (dt * 1e6);
	}
	return best;
}

/* ---- the MIT protocol ------------------------------------------------------ */

/* x on [lo, hi] as a bits-wide unsigned integer (clamped), and back. */
static unsigned to_uint(double x, double lo, double hi, int bits)
{
	unsigned top = (1u << bits) - 1;
	if (!(x > lo))
		return 0;
	if (x >= hi)
		return top;
	return (unsigned)((x - lo) * top / (hi - lo));
}

static double from_uint(unsigned raw, double lo, double hi, int bits)
{
	return raw * (hi - lo) / ((1u << bits) - 1) + lo;
}

static void pack_command(uint8_t d[8], double p, double v, double kp, double kd, double t, double t_range)
{
	unsigned pi = to_uint(p, -P_RANGE, P_RANGE, 16), vi = to_uint(v, -V_RANGE, V_RANGE, 12);
	unsigned kpi = to_uint(kp, 0, KP_MAX, 12), kdi = to_uint(kd, 0, KD_MAX, 12);
	unsigned ti = to_uint(t, -t_range, t_range, 12);
	d[0] = pi >> 8;
	d[1] = pi & 0xFF;
	d[2] = vi >> 4;
	d[3] = (vi & 0xF) << 4 | kpi >> 8;
	d[4] = kpi & 0xFF;
	d[5] = kdi >> 4;
	d[6] = (kdi & 0xF) << 4 | ti >> 8;
	d[7] = ti & 0xFF;
}

/* FF x7 then FC: enter motor mode; FD: leave it (the drive goes limp). */
static void pack_special(uint8_t d[8], uint8_t last)
{
	memset(d, 0xFF, 7);
	d[7] = last;
}

struct motor {
	int fd;
	canid_t id, reply_id;
	double t_range;
	long long lost; /* commands whose reply did not come within the wait */
};

struct state {
	double position, velocity, torque;
};

/* One command out, and its reply in, waited for up to wait_ms: 0 with the
 * reply's state, 1 when none came, -1 on a socket error. */
static int exchange(struct motor *m, const uint8_t data[8], int wait_ms, struct state *s)
{
	struct can_frame f;
	memset(&f, 0, sizeof f);
	f.can_id = m->id;
	f.can_dlc = 8;
	memcpy(f.data, data, 8);
	if (write(m->fd, &f, sizeof f) != sizeof f)
		return -1;
	/* The bind's filter lets only the reply id through; the motor's own id
	 * in d0 tells its reply from another motor's sharing that id. */
	double give_up = now_s() + wait_ms / 1e3;
	for (;;) {
		int left = (int)ceil((give_up - now_s()) * 1e3);
		struct pollfd p = { m->fd, POLLIN, 0 };
		int r = poll(&p, 1, left > 0 ? left : 0);
		if (r < 0 && errno == EINTR && !stop)
			continue;
		if (r <= 0) {
			m->lost++;
			return r < 0 ? -1 : 1;
		}
		if (read(m->fd, &f, sizeof f) != sizeof f)
			return -1;
		if (f.can_dlc != 6 || f.data[0] != (m->id & 0xFF))
			continue;
		s->position = from_uint((unsigned)f.data[1] << 8 | f.data[2], -P_RANGE, P_RANGE, 16);
		s->velocity = from_uint((unsigned)f.data[3] << 4 | f.data[4] >> 4, -V_RANGE, V_RANGE, 12);
		s->torque = from_uint((unsigned)(f.data[4] & 0xF) << 8 | f.data[5], -m->t_range, m->t_range, 12);
		return 0;
	}
}

static int open_can(const char *name, canid_t reply_id)
{
	int fd = socket(PF_CAN, SOCK_RAW, CAN_RAW);
	if (fd < 0)
		return -1;
	struct ifreq ifr;
	memset(&ifr, 0, sizeof ifr);
	snprintf(ifr.ifr_name, sizeof ifr.ifr_name, "%s", name);
	if (ioctl(fd, SIOCGIFINDEX, &ifr) < 0)
		return -1;
	/* Only the replies: a standard-id data frame on reply_id (or an
	 * extended one, as the motor sends an id above 0x7FF). */
	struct can_filter filter;
	if (reply_id > CAN_SFF_MASK) {
		filter.can_id = reply_id | CAN_EFF_FLAG;
		filter.can_mask = CAN_EFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG;
	} else {
		filter.can_id = reply_id;
		filter.can_mask = CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG;
	}
	if (setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FILTER, &filter, sizeof filter) < 0)
		return -1;
	struct sockaddr_can addr;
	memset(&addr, 0, sizeof addr);
	addr.can_family = AF_CAN;
	addr.can_ifindex = ifr.ifr_ifindex;
	if (bind(fd, (struct sockaddr *)&addr, sizeof addr) < 0)
		return -1;
	return fd;
}

/* ---- control ------------------------------------------------------------ */

static double wrap_pi(double a)
{
	a = fmod(a + M_PI, 2 * M_PI);
	return a < 0 ? a + M_PI : a - M_PI;
}

static void advance(struct timespec *t, long long ns)
{
	t->tv_nsec += ns;
	while (t->tv_nsec >= 1000000000L) {
		t->tv_nsec -= 1000000000L;
		t->tv_sec++;
	}
}

static int after(const struct timespec *a, const struct timespec *b)
{
	return a->tv_sec > b->tv_sec || (a->tv_sec == b->tv_sec && a->tv_nsec > b->tv_nsec);
}

static void usage(const char *argv0)
{
	fprintf(stderr, "usage: %s [--rate HZ] [--seconds S] [--work-us N] [--interface NAME] [--id N]"
			" [--reply-id N] [--torque-range NM] [--motor-pd]\n", argv0);
}

int main(int argc, char **argv)
{
	double rate = 500, seconds = 5, work_us = 0;
	const char *ifname = "can0";
	struct motor m = { -1, 1, 0, 4.0, 0 };
	int motor_pd = 0;
	static const struct option opts[] = {
		{ "rate", required_argument, NULL, 'r' },      { "seconds", required_argument, NULL, 's' },
		{ "work-us", required_argument, NULL, 'w' },   { "interface", required_argument, NULL, 'i' },
		{ "id", required_argument, NULL, 'n' },        { "reply-id", required_argument, NULL, 'R' },
		{ "torque-range", required_argument, NULL, 't' }, { "motor-pd", no_argument, NULL, 'P' },
		{ "help", no_argument, NULL, 'h' },            { NULL, 0, NULL, 0 },
	};
	int c;
	while ((c = getopt_long(argc, argv, "r:s:w:i:h", opts, NULL)) != -1) {
		switch (c) {
		case 'r': rate = atof(optarg); break;
		case 's': seconds = atof(optarg); break;
		case 'w': work_us = atof(optarg); break;
		case 'i': ifname = optarg; break;
		case 'n': m.id = (canid_t)strtoul(optarg, NULL, 0); break;
		case 'R': m.reply_id = (canid_t)strtoul(optarg, NULL, 0); break;
		case 't': m.t_range = atof(optarg); break;
		case 'P': motor_pd = 1; break;
		default: usage(argv[0]); return c == 'h' ? 0 : 2;
		}
	}
	if (rate <= 0 || seconds <= 0 || work_us < 0 || m.t_range <= 0 || m.id > CAN_SFF_MASK ||
	    m.reply_id > CAN_EFF_MASK) {
		fprintf(stderr, "%s: --rate, --seconds and --torque-range must be positive, --work-us not negative,"
				" --id a standard id\n", argv[0]);
		return 2;
	}
	m.fd = open_can(ifname, m.reply_id);
	if (m.fd < 0) {
		fprintf(stderr, "%s: %s: %s\n", argv[0], ifname, strerror(errno));
		return 1;
	}
	signal(SIGTERM, on_signal);
	signal(SIGINT, on_signal);

	/* A reply comes a few hundred microseconds after its command on a
	 * 1 Mbit/s bus; a period (10 ms at least) is a generous wait. */
	const long long period = (long long)(1e9 / rate);
	const int wait_ms = period / 1000000 > 10 ? (int)(period / 1000000) : 10;
	uint8_t d[8];
	struct state s = { 0, 0, 0 };
	pack_special(d, 0xFC);
	if (exchange(&m, d, 100, &s) != 0) {
		fprintf(stderr, "%s: motor %u does not answer on %s\n", argv[0], (unsigned)m.id, ifname);
		return 1;
	}
	/* The drive's own PD holds the rod up while the work is calibrated:
	 * tens of milliseconds here, as many times longer on a target CPU
	 * --cpu-scale times slower, and the rod must not fall meanwhile. The
	 * loop's first command takes over. */
	pack_command(d, s.position - wrap_pi(s.position - M_PI), 0, KP, KD, 0, m.t_range);
	if (exchange(&m, d, wait_ms, &s) < 0) {
		fprintf(stderr, "%s: %s: %s\n", argv[0], ifname, strerror(errno));
		return 1;
	}
	unsigned long long work = (unsigned long long)(work_us * (work_us > 0 ? rounds_per_us() : 0));
	/* Again, for the state as it is now: the loop's first law acts on it. */
	if (exchange(&m, d, wait_ms, &s) < 0) {
		fprintf(stderr, "%s: %s: %s\n", argv[0], ifname, strerror(errno));
		return 1;
	}

	struct timespec next;
	clock_gettime(CLOCK_MONOTONIC, &next);
	double start = now_s(), worst_recent = 0;
	long long cycles = 0, misses = 0;
	while (!stop && now_s() - start < seconds) {
		burn(work);
		double err = wrap_pi(s.position - M_PI); /* 0 when upright */
		if (motor_pd)
			/* The drive's own PD, about the upright nearest the rod. */
			pack_command(d, s.position - err, 0, KP, KD, 0, m.t_range);
		else
			pack_command(d, 0, 0, 0, 0, -KP * err - KD * s.velocity, m.t_range);
		if (exchange(&m, d, wait_ms, &s) < 0) {
			fprintf(stderr, "%s: %s: %s\n", argv[0], ifname, strerror(errno));
			return 1;
		}
		cycles++;
		/* How upright it is over the last 2 s of the run. */
		double away = fabs(wrap_pi(s.position - M_PI));
		if (now_s() - start > seconds - 2 && away > worst_recent)
			worst_recent = away;

		/* A late cycle is not skipped: the next starts at once, and the
		 * schedule catches up if the loop ever can. */
		advance(&next, period);
		struct timespec t;
		clock_gettime(CLOCK_MONOTONIC, &t);
		if (after(&t, &next))
			misses++;
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL);
	}
	double elapsed = now_s() - start;
	/* Leave the drive limp, as a controller should when it stops. */
	pack_special(d, 0xFD);
	exchange(&m, d, wait_ms, &s);
	close(m.fd);

	/* Balanced: within 0.1 rad of upright for its last 2 s. */
	int balanced = worst_recent < 0.1;
	printf("balance_can: %lld cycles in %.3f s (%.1f Hz), %lld deadline misses, %lld replies lost, final angle "
	       "%.3f rad, worst distance from upright over the last 2 s %.3f rad: %s\n",
	       cycles, elapsed, cycles / elapsed, misses, m.lost, s.position, worst_recent,
	       balanced ? "BALANCED" : "FELL");
	printf("cycles=%lld rate_hz=%.3f misses=%lld lost=%lld worst_last2s=%.6f balanced=%d\n", cycles,
	       cycles / elapsed, misses, m.lost, worst_recent, balanced);
	return 0;
}
