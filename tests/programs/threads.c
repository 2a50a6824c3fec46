/* threads MODE: multi-threaded controllers, each mode one scenario whose
 * figures (key=value lines, times in virtual ns from CLOCK_MONOTONIC) a
 * test checks against what virtual time must give; with each timed wait,
 * the process's CPU by the kernel's clock (not the CPU clock tcs answers,
 * so that a test bounds tcs's charges by the kernel's) over the same span,
 * read just before it began and just after it ended (*cpu_ns).
 *   loops        two threads, 1 kHz and 300 Hz periodic loops (200 us and
 *                1 ms of their own CPU per cycle) for 1 s: cycles, misses,
 *                and the misses the process's CPU explains (*_cpu_misses:
 *                see run_loop); when the 300 Hz loop began its last wait
 *                (slow_last_from_ns), and the CPU from there to the end
 *                (tail_cpu_ns)
 *   compute      main sleeps 10 ms while a worker computes 20 ms of CPU:
 *                when main woke, and the CPU of both threads by the
 *                kernel's thread clocks read just before main's clock
 *                read (*_before_wake_ns: the worker's as it last counted
 *                it) and just after (*_after_wake_ns); the stops tcs had
 *                made of the worker by then (worker_stops_by_wake)
 *                (compute slow-main: main at nice 19, so the worker
 *                finishes before main's turn)
 *   late-sleep   main computes 100 ms beside a worker that computes till
 *                told to stop, then sleeps 1 ms: when it asked and woke
 *   cond         condition variables: signalled at 1 ms (timedwait, both
 *                glibc versions, clockwait, a monotonic condattr), and
 *                timing out at 3 ms while another thread sleeps
 *   mutex        pthread_mutex_timedlock: times out at 2 ms, gets the lock
 *                when its holder unlocks at 5 ms
 *   sem          sem_timedwait times out at 3 ms; sem_clockwait is posted
 *                at 4 ms
 *   asleep       a worker blocked in read() on a pipe (outside the hooks)
 *                while main sleeps 5 ms, then writes to it
 *   poll         a worker sleeps 1 ms a thousand times while main polls
 *                its count every 100 us: when main saw the count reach
 *                1000, and how many times the worker was late */
#include <errno.h>
#include <pthread.h>
#include <semaphore.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "work.h"

#define MS 1000000LL

static long long t0, t0_cpu, t0_kernel_cpu, t0_main_thread_cpu;
static long long now(void)
{
	return clock_ns(CLOCK_MONOTONIC) - t0;
}

/* The process's CPU by the kernel's account: tcs charges no more than that,
 * so a wait is late by no more than it (the CPU clock the preload answers
 * would grow with any overcharge and excuse it). */
static long long cpu(void)
{
	return kernel_cpu_ns();
}

/* How far an estimated clock read may run ahead of the kernel's CPU
 * (libtcs_preload/cpu_estimate.c: its anchor is read again after 20 us). */
#define AHEAD_NS 20000LL

static void burn_cpu(long long ns) /* of this thread's own CPU, by the kernel's clock */
{
	compute_ns(CLOCK_THREAD_CPUTIME_ID, ns);
}

static void sleep_until(long long at)
{
	long long abs = t0 + at;
	struct timespec ts = { abs / 1000000000LL, abs % 1000000000LL };
	while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR)
		;
}

static struct timespec abs_on(clockid_t clock, long long from_now)
{
	long long t = clock_ns(clock) + from_now;
	struct timespec ts = { t / 1000000000LL, t % 1000000000LL };
	return ts;
}

/* ---- loops ---- */
struct loop {
	long long period, work, cycles, misses, cpu_misses, last_from, last_from_cpu;
};

static void *run_loop(void *arg)
{
	struct loop *l = arg;
	long long next = 0, round_start = t0_kernel_cpu, debt = 0;
	while (next < 1000 * MS) {
		burn_cpu(l->work);
		l->cycles++;
		next += l->period;
		long long before = kernel_cpu_ns(), at = now(), k = kernel_cpu_ns();
		if (at > next)
			l->misses++;
		/* Virtual time passes by the process's CPU, both threads' (or
		 * jumps while all wait, never past this loop's release). So
		 * this loop is late at a check only if the process's CPU over
		 * the rounds since it was last on time, each from one check to
		 * the next (its wait included), by the kernel's clock, exceeds
		 * their periods: cpu_misses counts the checks after which that
		 * debt is positive. On one core the other loop's bursts make
		 * some; for work that fits, only a pause of the machine
		 * (charged as CPU) makes more. A round's CPU is read from just
		 * before one check's look at the clock to just after the
		 * next's (all of the time between them in it). */
		long long round = k - round_start;
		round_start = before;
		debt = debt + round + AHEAD_NS - l->period > 0 ? debt + round + AHEAD_NS - l->period : 0;
		l->cpu_misses += debt > 0;
		l->last_from_cpu = cpu();
		l->last_from = now();
		sleep_until(next);
	}
	return NULL;
}

static int mode_loops(void)
{
	struct loop fast = { 1 * MS, 200000, 0, 0, 0, 0, 0 }, slow = { 3333333, 1 * MS, 0, 0, 0, 0, 0 };
	pthread_t a, b;
	pthread_create(&a, NULL, run_loop, &fast);
	pthread_create(&b, NULL, run_loop, &slow);
	pthread_join(a, NULL);
	pthread_join(b, NULL);
	long long elapsed = now(), end_cpu = cpu();
	printf("fast_cycles=%lld fast_misses=%lld slow_cycles=%lld slow_misses=%lld elapsed_ns=%lld\n", fast.cycles,
	       fast.misses, slow.cycles, slow.misses, elapsed);
	printf("fast_cpu_misses=%lld slow_cpu_misses=%lld slow_last_from_ns=%lld tail_cpu_ns=%lld\n", fast.cpu_misses,
	       slow.cpu_misses, slow.last_from, end_cpu - slow.last_from_cpu);
	return 0;
}

/* ---- compute ---- */
static volatile long long worker_done_ns; /* the worker's CPU so far, from c0 */
static volatile long long worker_start_cpu; /* its CPU at c0 */
static volatile long worker_stops; /* stops tcs made of it (it makes no wait) */

static void *compute(void *arg)
{
	(void)arg;
	long long c0 = kernel_clock_ns(CLOCK_THREAD_CPUTIME_ID);
	long s0 = kernel_thread_voluntary_switches();
	worker_start_cpu = c0; /* its CPU from its creation to here */
	while (worker_done_ns < 20 * MS) {
		work(1000);
		worker_stops = kernel_thread_voluntary_switches() - s0;
		worker_done_ns = kernel_clock_ns(CLOCK_THREAD_CPUTIME_ID) - c0;
	}
	return NULL;
}

/* slow_main: main at nice 19 against the worker's 0, so that when its
 * sleep ends the kernel lets the worker finish first (the case a 10 ms
 * accounting error once hid in: the worker's CPU before main's turn was
 * taken for main's hook's own). */
static int mode_compute(int slow_main)
{
	pthread_t w;
	if (slow_main)
		setpriority(PRIO_PROCESS, (id_t)syscall(SYS_gettid), 19);
	pthread_create(&w, NULL, compute, NULL);
	struct timespec ten = { 0, 10 * MS };
	clockid_t worker_clock;
	pthread_getcpuclockid(w, &worker_clock);
	nanosleep(&ten, NULL);
	/* The worker may run between any two of these reads (the kernel
	 * shares the core between the two): what it counted before main's
	 * clock read is no more than its CPU then, its clock read after no
	 * less; so for main's own. */
	long long worker_before = worker_start_cpu + worker_done_ns;
	long long main_before = kernel_clock_ns(CLOCK_THREAD_CPUTIME_ID) - t0_main_thread_cpu;
	long long woke = now();
	long stops_after = worker_stops; /* (after main's read: no fewer than by then) */
	long long worker_after = kernel_clock_ns(worker_clock);
	long long main_after = kernel_clock_ns(CLOCK_THREAD_CPUTIME_ID) - t0_main_thread_cpu;
	pthread_join(w, NULL);
	printf("main_woke_ns=%lld end_ns=%lld\n", woke, now());
	printf("worker_cpu_before_wake_ns=%lld worker_cpu_after_wake_ns=%lld\n", worker_before, worker_after);
	printf("main_cpu_before_wake_ns=%lld main_cpu_after_wake_ns=%lld\n", main_before, main_after);
	printf("worker_stops_by_wake=%ld worker_stops=%ld\n", stops_after, worker_stops);
	return 0;
}

/* ---- late-sleep ---- */
static volatile int worker_stop;

static void *compute_till_told(void *arg)
{
	(void)arg;
	long long c0 = kernel_clock_ns(CLOCK_THREAD_CPUTIME_ID);
	while (!worker_stop && kernel_clock_ns(CLOCK_THREAD_CPUTIME_ID) - c0 < 5000 * MS)
		work(1000);
	return NULL;
}

/* A sleep begun deep into a slice of the process (both threads computed
 * 100 ms since it last waited): its end is checked from the slice's start,
 * not from the sleep's. */
static int mode_late_sleep(void)
{
	pthread_t w;
	pthread_create(&w, NULL, compute_till_told, NULL);
	burn_cpu(100 * MS);
	struct timespec one = { 0, 1 * MS };
	long long asked = now();
	nanosleep(&one, NULL);
	long long woke = now();
	worker_stop = 1;
	pthread_join(w, NULL);
	printf("asked_ns=%lld woke_ns=%lld\n", asked, woke);
	return 0;
}

/* ---- cond ---- */
static pthread_mutex_t mu = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t cv = PTHREAD_COND_INITIALIZER;
static int flag;

/* The condition-variable ABI of glibc before 2.3.2, as old binaries call it. */
extern int old_cond_timedwait(void *c, pthread_mutex_t *m, const struct timespec *t);
extern int old_cond_signal(void *c);
__asm__(".symver old_cond_timedwait, pthread_cond_timedwait@GLIBC_2.2.5");
__asm__(".symver old_cond_signal, pthread_cond_signal@GLIBC_2.2.5");
static void *old_cv[8]; /* an old condition variable: a pointer, zero to start */

static int variant;
static pthread_cond_t *signalled; /* the one the waiter waits on */
static void *signal_at_1ms(void *arg)
{
	(void)arg;
	sleep_until(now() + 1 * MS);
	pthread_mutex_lock(&mu);
	flag = 1;
	if (variant == 1)
		old_cond_signal(old_cv);
	else
		pthread_cond_signal(signalled);
	pthread_mutex_unlock(&mu);
	return NULL;
}

static int cond_wait_variant(int v, pthread_cond_t *c)
{
	variant = v;
	signalled = c;
	flag = 0;
	pthread_t s;
	pthread_mutex_lock(&mu);
	long long c0 = cpu(), start = now();
	pthread_create(&s, NULL, signal_at_1ms, NULL);
	int r = 0;
	while (!flag && r == 0) {
		if (v == 1) {
			struct timespec at = abs_on(CLOCK_REALTIME, 10 * MS);
			r = old_cond_timedwait(old_cv, &mu, &at);
		} else if (v == 2) {
			struct timespec at = abs_on(CLOCK_MONOTONIC, 10 * MS);
			r = pthread_cond_clockwait(c, &mu, CLOCK_MONOTONIC, &at);
		} else if (v == 3) {
			struct timespec at = abs_on(CLOCK_MONOTONIC, 10 * MS); /* c has a monotonic condattr */
			r = pthread_cond_timedwait(c, &mu, &at);
		} else {
			struct timespec at = abs_on(CLOCK_REALTIME, 10 * MS);
			r = pthread_cond_timedwait(c, &mu, &at);
		}
	}
	long long took = now() - start, took_cpu = cpu() - c0;
	pthread_mutex_unlock(&mu);
	pthread_join(s, NULL);
	printf("variant=%d result=%d signalled_after_ns=%lld cpu_ns=%lld\n", v, r, took, took_cpu);
	return 0;
}

static void *sleeper(void *arg)
{
	(void)arg;
	struct timespec d = { 0, 50 * MS };
	nanosleep(&d, NULL);
	return NULL;
}

static int mode_cond(void)
{
	pthread_condattr_t a;
	pthread_cond_t mono;
	pthread_condattr_init(&a);
	pthread_condattr_setclock(&a, CLOCK_MONOTONIC);
	pthread_cond_init(&mono, &a);
	cond_wait_variant(0, &cv);
	cond_wait_variant(1, &cv);
	cond_wait_variant(2, &cv);
	cond_wait_variant(3, &mono);
	/* Nobody signals; another thread sleeps meanwhile. */
	pthread_t s;
	pthread_create(&s, NULL, sleeper, NULL);
	pthread_mutex_lock(&mu);
	long long c0 = cpu(), start = now();
	struct timespec at = abs_on(CLOCK_REALTIME, 3 * MS);
	int r = pthread_cond_timedwait(&cv, &mu, &at);
	long long took = now() - start, took_cpu = cpu() - c0;
	pthread_mutex_unlock(&mu);
	pthread_join(s, NULL);
	printf("timeout_result=%d timed_out_after_ns=%lld timed_out_cpu_ns=%lld sleeper_done_ns=%lld\n", r, took, took_cpu,
	       now());
	return 0;
}

/* ---- mutex ---- */
static void *lock_then_unlock_at_5ms(void *arg)
{
	(void)arg;
	pthread_mutex_lock(&mu);
	flag = 1;
	sleep_until(5 * MS);
	pthread_mutex_unlock(&mu);
	return NULL;
}

static int mode_mutex(void)
{
	pthread_t h;
	pthread_create(&h, NULL, lock_then_unlock_at_5ms, NULL);
	while (!__atomic_load_n(&flag, __ATOMIC_ACQUIRE))
		sched_yield();
	long long c0 = cpu(), start = now();
	struct timespec at = abs_on(CLOCK_REALTIME, 2 * MS);
	int r1 = pthread_mutex_timedlock(&mu, &at);
	long long t1 = now() - start, c1 = cpu() - c0;
	at = abs_on(CLOCK_REALTIME, 10 * MS);
	int r2 = pthread_mutex_timedlock(&mu, &at);
	long long t2 = now(), c2 = cpu() - t0_cpu;
	if (r2 == 0)
		pthread_mutex_unlock(&mu);
	pthread_join(h, NULL);
	printf("first_result=%d first_after_ns=%lld first_cpu_ns=%lld second_result=%d second_at_ns=%lld second_cpu_ns=%lld\n",
	       r1, t1, c1, r2, t2, c2);
	return 0;
}

/* ---- sem ---- */
static sem_t sem;
static void *post_at_4ms(void *arg)
{
	(void)arg;
	sleep_until(4 * MS);
	sem_post(&sem);
	return NULL;
}

static int mode_sem(void)
{
	sem_init(&sem, 0, 0);
	long long c0 = cpu(), start = now();
	struct timespec at = abs_on(CLOCK_REALTIME, 3 * MS);
	int r1 = sem_timedwait(&sem, &at);
	int e1 = r1 ? errno : 0;
	long long t1 = now() - start, c1 = cpu() - c0;
	pthread_t p;
	pthread_create(&p, NULL, post_at_4ms, NULL);
	at = abs_on(CLOCK_MONOTONIC, 50 * MS);
	int r2 = sem_clockwait(&sem, CLOCK_MONOTONIC, &at);
	long long t2 = now(), c2 = cpu() - t0_cpu;
	pthread_join(p, NULL);
	printf("timedwait_errno=%s timedwait_after_ns=%lld timedwait_cpu_ns=%lld clockwait_result=%d clockwait_at_ns=%lld "
	       "clockwait_cpu_ns=%lld\n",
	       e1 == ETIMEDOUT ? "ETIMEDOUT" : strerror(e1), t1, c1, r2, t2, c2);
	return 0;
}

/* ---- asleep ---- */
static int pipefd[2];
static long long got_at;
static void *reader(void *arg)
{
	(void)arg;
	char c;
	if (read(pipefd[0], &c, 1) == 1)
		got_at = now();
	return NULL;
}

static int mode_asleep(void)
{
	if (pipe(pipefd) < 0)
		return 1;
	pthread_t r;
	pthread_create(&r, NULL, reader, NULL);
	struct timespec five = { 0, 5 * MS };
	nanosleep(&five, NULL);
	long long woke = now(), woke_cpu = cpu() - t0_cpu;
	if (write(pipefd[1], "x", 1) != 1)
		return 1;
	pthread_join(r, NULL);
	printf("main_woke_ns=%lld main_woke_cpu_ns=%lld reader_got_ns=%lld\n", woke, woke_cpu, got_at);
	return 0;
}

/* ---- poll ---- */
static volatile long polled_count;
static long worker_late;

static void *counting(void *arg)
{
	(void)arg;
	struct timespec ms = { 0, MS };
	for (long i = 1; i <= 1000; i++) {
		nanosleep(&ms, NULL);
		if (now() != i * MS)
			worker_late++;
		polled_count = i;
	}
	return NULL;
}

static int mode_poll(void)
{
	pthread_t w;
	pthread_create(&w, NULL, counting, NULL);
	struct timespec poll_period = { 0, 100000 };
	while (polled_count < 1000)
		nanosleep(&poll_period, NULL);
	long long seen = now();
	pthread_join(w, NULL);
	printf("seen_ns=%lld worker_late=%ld\n", seen, worker_late);
	return 0;
}

int main(int argc, char **argv)
{
	/* The CPU figures from the start are read before it: all of the time
	 * from t0 on is in them (main's thread clock last: it is not ahead of
	 * t0 by more than one read). */
	t0_kernel_cpu = kernel_cpu_ns();
	t0_cpu = cpu();
	t0_main_thread_cpu = kernel_clock_ns(CLOCK_THREAD_CPUTIME_ID);
	t0 = clock_ns(CLOCK_MONOTONIC);
	const char *mode = argc > 1 ? argv[1] : "";
	if (!strcmp(mode, "loops"))
		return mode_loops();
	if (!strcmp(mode, "compute"))
		return mode_compute(argc > 2 && !strcmp(argv[2], "slow-main"));
	if (!strcmp(mode, "late-sleep"))
		return mode_late_sleep();
	if (!strcmp(mode, "cond"))
		return mode_cond();
	if (!strcmp(mode, "mutex"))
		return mode_mutex();
	if (!strcmp(mode, "sem"))
		return mode_sem();
	if (!strcmp(mode, "asleep"))
		return mode_asleep();
	if (!strcmp(mode, "poll"))
		return mode_poll();
	fprintf(stderr, "usage: threads loops|compute|late-sleep|cond|mutex|sem|asleep|poll\n");
	return 2;
}
