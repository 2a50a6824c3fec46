/* The contexts the idioms program makes its call from: main, a thread,
 * a handler, a nested handler, fork and vfork children of a threaded
 * program. */
#include "calls_timers.h"
#include "calls_world.h"
#include "common.h"
#include "contexts.h"
#include "table.h"

/* ---- signal handlers ---- */

void on_wake(int sig, siginfo_t *si, void *uc)
{
	(void)uc;
	int w = sig - SIGRTMIN;
	wake_code[w] = si->si_code;
	wake_pid[w] = si->si_pid;
	wake_value[w] = si->si_value.sival_int;
	wakes[w]++;
}

/* SIGRTMAX: what a probe timer that never expires would send. */
volatile int strays;

void on_stray(int sig)
{
	(void)sig;
	strays++;
}

/* fn handles sig, with `also` (or 0) blocked while it runs. */
static void on_masking(int sig, void (*fn)(int), int also)
{
	struct sigaction sa = { .sa_handler = fn }; /* no SA_RESTART: calls see EINTR */
	sigemptyset(&sa.sa_mask);
	if (also)
		sigaddset(&sa.sa_mask, also);
	if (sigaction(sig, &sa, NULL) != 0)
		die("sigaction");
}

void on(int sig, void (*fn)(int))
{
	on_masking(sig, fn, 0);
}

int the_call, the_flow = -1;
volatile int done, inside, in_alarm, gave_up;
volatile long long handler_runs, nested_runs, inside_hits, lone_calls, goal_calls;
long long start_ns;

/* handler: the CALL, interrupting main's loop over INTERRUPTED. */
static void on_alarm_call(int sig)
{
	(void)sig;
	int saved = errno;
	if (!done && goal_calls < ROUNDS) { /* none beyond the goal: it is compared */
		handler_runs++;
		if (inside)
			inside_hits++;
		do_call(the_call, WHO_HANDLER, ROLE_CALL);
		goal_calls++;
	}
	errno = saved;
}

/* nested: the SIGALRM handler loops over INTERRUPTED until a SIGUSR1 has
 * come (whose handler makes the CALL), or NEST_CAP_NS. */
static void on_alarm_flow(int sig)
{
	(void)sig;
	int saved = errno;
	if (!done && goal_calls < ROUNDS) { /* none beyond the goal: it is compared */
		handler_runs++;
		long long seen = nested_runs, t0 = mono_ns();
		in_alarm = 1;
		while (nested_runs == seen && !done && mono_ns() - t0 < NEST_CAP_NS) {
			inside = 1;
			do_call(the_flow, WHO_HANDLER, ROLE_FLOW);
			inside = 0;
		}
		in_alarm = 0;
	}
	errno = saved;
}

static void on_usr1(int sig)
{
	(void)sig;
	int saved = errno;
	if (!done && goal_calls < ROUNDS) { /* none beyond the goal: it is compared */
		int nested = in_alarm;
		nested_runs++;
		if (inside)
			inside_hits++;
		do_call(the_call, WHO_NESTED, ROLE_CALL);
		if (nested)
			goal_calls++;
		else
			lone_calls++;
	}
	errno = saved;
}

/* ---- contexts ---- */

static int over_time(void)
{
	if (mono_ns() - start_ns > GIVE_UP_NS)
		gave_up = 1;
	return gave_up;
}

/* Blocks every signal a handler of ours takes: what a helper thread
 * starts with, so that those go to the thread whose they are (SIGTERM
 * and the like still end the process). */
static void block_ours(sigset_t *old)
{
	sigset_t ours;
	sigemptyset(&ours);
	sigaddset(&ours, SIGALRM);
	sigaddset(&ours, SIGUSR1);
	sigaddset(&ours, SIGRTMAX);
	for (int w = 0; w < WHOS; w++)
		sigaddset(&ours, wake_sig(w));
	pthread_sigmask(SIG_BLOCK, &ours, old);
}

void run_main(void)
{
	setup(WHO_MAIN, the_call);
	for (int i = 0; i < ROUNDS; i++, goal_calls++)
		do_call(the_call, WHO_MAIN, ROLE_CALL);
}

static volatile int thread_done;

static void *call_thread(void *arg)
{
	(void)arg;
	sigset_t mine;
	sigemptyset(&mine);
	sigaddset(&mine, wake_sig(WHO_MAIN));
	pthread_sigmask(SIG_UNBLOCK, &mine, NULL);
	setup(WHO_MAIN, the_call); /* its wake timer signals this thread */
	for (int i = 0; i < ROUNDS; i++, goal_calls++)
		do_call(the_call, WHO_MAIN, ROLE_CALL);
	thread_done = 1;
	return NULL;
}

/* The CALL in a second thread; main, with the wake signals blocked (so
 * that one sent to the process is the calling thread's), sleeps meanwhile. */
void run_thread(void)
{
	sigset_t old, wake;
	sigemptyset(&wake);
	for (int w = 0; w < WHOS; w++)
		sigaddset(&wake, wake_sig(w));
	pthread_sigmask(SIG_BLOCK, &wake, &old);
	pthread_t t;
	if (pthread_create(&t, NULL, call_thread, NULL) != 0)
		die("pthread_create");
	setup(WHO_HANDLER, call_id("nanosleep"));
	while (!thread_done)
		do_call(call_id("nanosleep"), WHO_HANDLER, ROLE_FLOW);
	pthread_join(t, NULL);
	pthread_sigmask(SIG_SETMASK, &old, NULL);
}

int driver_itimer;
static timer_t driver_timer, nest_timer;

static void arm_driver(void)
{
	if (driver_itimer) {
		if (setitimer(ITIMER_REAL, &driver_spec, NULL) != 0)
			die("setitimer");
		return;
	}
	struct sigevent ev = { .sigev_notify = SIGEV_SIGNAL, .sigev_signo = SIGALRM };
	struct itimerspec on = { ts_of(PERIOD_NS), ts_of(PERIOD_NS) };
	if (timer_create(CLOCK_MONOTONIC, &ev, &driver_timer) != 0 || timer_settime(driver_timer, 0, &on, NULL) != 0)
		die("timer_create");
}

static void disarm_driver(void)
{
	done = 1;
	if (driver_itimer) {
		struct itimerval off = { { 0, 0 }, { 0, 0 } };
		setitimer(ITIMER_REAL, &off, NULL);
	} else {
		timer_delete(driver_timer);
	}
}

void run_handler(void)
{
	setup(WHO_MAIN, the_flow);
	setup(WHO_HANDLER, the_call);
	on(SIGALRM, on_alarm_call);
	arm_driver();
	while (goal_calls < ROUNDS && !over_time()) {
		inside = 1;
		do_call(the_flow, WHO_MAIN, ROLE_FLOW);
		inside = 0;
	}
	disarm_driver();
}

static pthread_t main_thread;

/* nested/kill's source of SIGUSR1: another thread, every NEST_NS. */
static void *killer(void *arg)
{
	(void)arg;
	struct timespec ts = ts_of(NEST_NS);
	while (!done) {
		nanosleep(&ts, NULL);
		if (!done)
			pthread_kill(main_thread, SIGUSR1);
	}
	return NULL;
}

void run_nested(int by_thread)
{
	setup(WHO_HANDLER, the_flow);
	setup(WHO_NESTED, the_call);
	on(SIGALRM, on_alarm_flow);
	/* SIGALRM waits while SIGUSR1 is handled: the nesting is the other way
	 * round (a SIGALRM handler inside SIGUSR1's would wait for a SIGUSR1
	 * that cannot come) */
	on_masking(SIGUSR1, on_usr1, SIGALRM);
	pthread_t t;
	main_thread = pthread_self();
	if (by_thread) {
		sigset_t old;
		block_ours(&old); /* the killer thread handles no signal */
		if (pthread_create(&t, NULL, killer, NULL) != 0)
			die("pthread_create");
		pthread_sigmask(SIG_SETMASK, &old, NULL);
	} else {
		struct sigevent ev = { .sigev_notify = SIGEV_SIGNAL, .sigev_signo = SIGUSR1 };
		struct itimerspec on = { ts_of(NEST_NS), ts_of(NEST_NS) };
		if (timer_create(CLOCK_MONOTONIC, &ev, &nest_timer) != 0 || timer_settime(nest_timer, 0, &on, NULL) != 0)
			die("timer_create");
	}
	arm_driver();
	while (goal_calls < ROUNDS && !over_time())
		pause();
	disarm_driver();
	if (by_thread)
		pthread_join(t, NULL);
	else
		timer_delete(nest_timer);
}

/* fork and vfork: two threads keep calling timer_settime, getitimer and
 * clock_gettime (sleeping a little every 16 rounds), so that a fork finds
 * them inside those hooks. */
static volatile int churn_stop;

static void *churn(void *arg)
{
	(void)arg;
	timer_t t;
	struct sigevent none = { .sigev_notify = SIGEV_NONE };
	if (timer_create(CLOCK_MONOTONIC, &none, &t) != 0)
		return NULL;
	struct itimerspec on = { { 0, 0 }, ts_of(PROBE_NS) };
	struct itimerval iv;
	struct timespec ts, nap = ts_of(200000);
	while (!churn_stop) {
		for (int i = 0; i < 16; i++) {
			timer_settime(t, 0, &on, NULL);
			getitimer(ITIMER_REAL, &iv);
			clock_gettime(CLOCK_MONOTONIC, &ts);
		}
		nanosleep(&nap, NULL);
	}
	timer_delete(t);
	return NULL;
}

static pthread_t churners[2];

static void churn_start(void)
{
	sigset_t old;
	block_ours(&old);
	for (int i = 0; i < 2; i++)
		if (pthread_create(&churners[i], NULL, churn, NULL) != 0)
			die("pthread_create");
	pthread_sigmask(SIG_SETMASK, &old, NULL);
}

static void churn_end(void)
{
	churn_stop = 1;
	for (int i = 0; i < 2; i++)
		pthread_join(churners[i], NULL);
}

/* A fork child starts from nothing: its CPU clocks from 0, no timers. */
static void child_reset(void)
{
	memset(&S, 0, sizeof S);
	S.sleep_min[0] = S.sleep_min[1] = -1;
	S.over_max[0] = S.over_max[1] = -1;
	S.slack = -1;
	seen_process = seen_thread = seen_clock = seen_times_cpu = seen_rusage = 0;
	memset(flows, 0, sizeof flows);
}

static void merge(const struct stats *c)
{
	for (int r = 0; r < 2; r++) {
		S.calls[r] += c->calls[r];
		S.sleeps[r] += c->sleeps[r];
		if (c->sleep_min[r] >= 0)
			at_least(&S.sleep_min[r], c->sleep_min[r]);
		at_most(&S.sleep_max[r], c->sleep_max[r]);
		at_most(&S.over_max[r], c->over_max[r]);
	}
	S.eintr += c->eintr;
	S.absent += c->absent;
	S.failures += c->failures;
	if (c->first_set && !S.first_set) {
		S.first_set = 1;
		S.first_call = c->first_call;
		S.first_what = c->first_what;
		S.first_errno = c->first_errno;
		S.first_value = c->first_value;
		S.first_role = c->first_role;
	}
	if (c->slack >= 0)
		S.slack = c->slack;
}

void run_fork(void)
{
	struct ctx c = { &flows[WHO_MAIN], WHO_MAIN, ROLE_CALL, "fork_context" };
	churn_start();
	for (int i = 0; i < ROUNDS && !over_time(); i++) {
		int p[2];
		if (pipe2(p, O_CLOEXEC) != 0)
			die("pipe");
		pid_t pid = fork();
		if (pid < 0)
			die("fork");
		if (pid == 0) {
			close(p[0]);
			child_reset();
			setup(WHO_MAIN, the_call);
			do_call(the_call, WHO_MAIN, ROLE_CALL);
			ssize_t n = write(p[1], &S, sizeof S);
			_exit(n == (ssize_t)sizeof S && S.failures == 0 ? 0 : 1);
		}
		close(p[1]);
		struct stats got;
		size_t have = 0;
		while (have < sizeof got) {
			ssize_t n = read(p[0], (char *)&got + have, sizeof got - have);
			if (n < 0 && errno == EINTR)
				continue;
			if (n <= 0)
				break;
			have += n;
		}
		close(p[0]);
		int st = reap(&c, pid);
		if (have == sizeof got)
			merge(&got);
		else
			fail(&c, "child_no_report", 0);
		exited_zero(&c, st);
		goal_calls++;
	}
	churn_end();
}

void run_vfork(void)
{
	struct ctx c = { &flows[WHO_MAIN], WHO_MAIN, ROLE_CALL, "vfork_context" };
	int exec = strcmp(calls[the_call].name, "exec") == 0;
	clockid_t clk = strcmp(calls[the_call].name, "clock_real") == 0 ? CLOCK_REALTIME : CLOCK_MONOTONIC;
	churn_start();
	for (int i = 0; i < ROUNDS && !over_time(); i++) {
		pid_t pid = vfork();
		if (pid < 0)
			die("vfork");
		if (pid == 0) {
			if (exec)
				execl("/bin/true", "true", (char *)NULL);
			else {
				struct timespec ts;
				clock_gettime(clk, &ts);
			}
			_exit(exec ? 127 : 0);
		}
		exited_zero(&c, reap(&c, pid));
		sum(&S.calls[ROLE_CALL], 1);
		goal_calls++;
	}
	churn_end();
}
