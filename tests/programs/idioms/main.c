/* idioms CONTEXT CALL [INTERRUPTED]: the idiom corpus's one program
 * (docs/DESIGN.md §10; tests/corpus/cases.py makes its cases and
 * run_corpus.py runs them natively and under tcs-run). It makes one hooked
 * CALL ROUNDS (20) times from one CONTEXT:
 *   main            the main thread
 *   thread          a second thread, while main sleeps in short nanosleeps
 *   handler/itimer  a SIGALRM handler of a periodic ITIMER_REAL (or, for
 *   handler/posix   /posix, timer_create) timer, interrupting main while
 *                   main loops over the INTERRUPTED call
 *   nested/timer    a SIGUSR1 handler (from a timer_create timer, or from
 *   nested/kill     another thread's pthread_kill) interrupting a SIGALRM
 *                   handler that loops over the INTERRUPTED call until it
 *                   comes (only CALLs made inside that handler count)
 *   fork            20 children of a program whose two other threads keep
 *                   calling timer_settime, getitimer and clock_gettime; each
 *                   makes the CALL once and _exits
 *   vfork           20 vfork children (same threads) that read a clock and
 *                   _exit, or exec /bin/true: all POSIX lets them do
 * A SIGALRM driver is ITIMER_REAL unless the CALL or INTERRUPTED needs
 * ITIMER_REAL itself (alarm; setitimer in main; setitimer in a nested
 * handler), then a POSIX timer.
 * Every call checks what POSIX and Linux promise of it (clocks never go
 * back, a timer never shows more left than it was armed for, a signal sent
 * to oneself is handled before the call returns, ...), and every wait with
 * a timeout is measured on CLOCK_MONOTONIC never to end early, restarted
 * after EINTR with what is left, as real code does. Only async-signal-safe
 * work runs in handlers, except in the calls that are the point (fopen,
 * system).
 * Prints key=value lines and exits 0 if every check held, 1 if not, 2 on
 * a usage error, 3 if what it sets up first failed. `idioms --list` prints the calls, one a line:
 * name, then flags: posix (POSIX lists it async-signal-safe),
 * interrupted (main may loop over it under a handler), vfork.
 * Natively /dev/tcs does not exist: a device call then counts
 * device_absent, and is no failure (the runner requires 0 under tcs). */
#include <errno.h>
#include "calls_timers.h"
#include "calls_world.h"
#include "common.h"
#include "contexts.h"
#include "table.h"

static int usage(void)
{
	fprintf(stderr, "usage: idioms main|thread|fork|vfork CALL\n"
			"       idioms handler/itimer|handler/posix|nested/timer|nested/kill CALL INTERRUPTED\n"
			"       idioms --list\n");
	return 2;
}

static int needs_itimer(int id)
{
	const char *n = calls[id].name;
	return !strcmp(n, "alarm") || !strcmp(n, "setitimer") || !strcmp(n, "getitimer");
}

int main(int argc, char **argv)
{
	if (argc == 2 && !strcmp(argv[1], "--list")) {
		for (int i = 0; i < ncalls; i++)
			printf("%s%s%s%s\n", calls[i].name, calls[i].flags & F_POSIX ? " posix" : "",
			       calls[i].flags & F_INTERRUPTED ? " interrupted" : "", calls[i].flags & F_VFORK ? " vfork" : "");
		return 0;
	}
	if (argc < 3)
		return usage();
	const char *context = argv[1];
	int handler = !strncmp(context, "handler/", 8), nested = !strncmp(context, "nested/", 7);
	the_call = call_id(argv[2]);
	if (the_call < 0 || argc != (handler || nested ? 4 : 3))
		return usage();
	if (handler || nested) {
		the_flow = call_id(argv[3]);
		if (the_flow < 0 || !(calls[the_flow].flags & F_INTERRUPTED))
			return usage();
	}
	const char *call = calls[the_call].name, *flow = the_flow >= 0 ? calls[the_flow].name : "-";

	/* Who owns ITIMER_REAL: the driver, unless a call arms it for itself
	 * (alarm anywhere, setitimer in the interrupted flow), or in nested,
	 * a SIGUSR1 handler would re-arm it (every 1.5 ms, for 2 ms: it would
	 * never expire). */
	int itimer_needed = !strcmp(call, "alarm") || !strcmp(flow, "alarm") || !strcmp(flow, "setitimer") ||
			    (nested && !strcmp(call, "setitimer"));
	if (handler)
		driver_itimer = !strcmp(context, "handler/itimer");
	else if (nested)
		driver_itimer = !itimer_needed;
	if (driver_itimer && itimer_needed) {
		fprintf(stderr, "idioms: %s %s needs ITIMER_REAL: use handler/posix\n", call, flow);
		return 2;
	}
	if (driver_itimer)
		itimer_use = IT_DRIVER;
	else if ((handler || nested) && needs_itimer(the_call) && needs_itimer(the_flow))
		itimer_use = IT_SHARED;

	struct sigaction sa = { .sa_sigaction = on_wake, .sa_flags = SA_SIGINFO };
	sigemptyset(&sa.sa_mask);
	for (int w = 0; w < WHOS; w++)
		if (sigaction(wake_sig(w), &sa, NULL) != 0)
			die("sigaction");

	on(SIGRTMAX, on_stray);

	start_ns = mono_ns();
	if (!strcmp(context, "main"))
		run_main();
	else if (!strcmp(context, "thread"))
		run_thread();
	else if (!strcmp(context, "handler/itimer") || !strcmp(context, "handler/posix"))
		run_handler();
	else if (!strcmp(context, "nested/timer") || !strcmp(context, "nested/kill"))
		run_nested(!strcmp(context, "nested/kill"));
	else if (!strcmp(context, "fork"))
		run_fork();
	else if (!strcmp(context, "vfork") && (calls[the_call].flags & F_VFORK))
		run_vfork();
	else
		return usage();
	long long elapsed = mono_ns() - start_ns;

	int ok = S.failures == 0 && goal_calls == ROUNDS && !gave_up && !strays;
	printf("context=%s\ncall=%s\ninterrupted=%s\ndriver=%s\n", context, call, flow,
	       handler || nested ? (driver_itimer ? "itimer" : "posix") : "-");
	printf("calls=%lld\ncontext_calls=%lld\nflow_calls=%lld\n", goal_calls, S.calls[ROLE_CALL], S.calls[ROLE_FLOW]);
	printf("handler_runs=%lld\nnested_runs=%lld\nlone_calls=%lld\ninside_hits=%lld\n", handler_runs, nested_runs, lone_calls,
	       inside_hits);
	printf("failures=%lld\n", S.failures);
	if (S.first_set && S.first_errno)
		printf("first_failure=%s:%s:%s\n", S.first_call, S.first_what,
		       strerrorname_np(S.first_errno) ? strerrorname_np(S.first_errno) : "?");
	else if (S.first_set)
		printf("first_failure=%s:%s:%d\n", S.first_call, S.first_what, S.first_value);
	else
		printf("first_failure=-\n");
	printf("first_failure_in=%s\n", !S.first_set ? "-" : S.first_role == ROLE_CALL ? "call" : "interrupted");
	printf("call_sleeps=%lld\ncall_sleep_min_ns=%lld\ncall_sleep_max_ns=%lld\ncall_sleep_over_max_ns=%lld\n", S.sleeps[0],
	       S.sleep_min[0], S.sleep_max[0], S.over_max[0]);
	printf("flow_sleeps=%lld\nflow_sleep_min_ns=%lld\nflow_sleep_max_ns=%lld\nflow_sleep_over_max_ns=%lld\n", S.sleeps[1],
	       S.sleep_min[1], S.sleep_max[1], S.over_max[1]);
	printf("stray_signals=%d\n", strays);
	printf("eintr=%lld\ndevice_absent=%lld\ntimerslack_ns=%lld\ngave_up=%d\nelapsed_ns=%lld\nok=%d\n", S.eintr, S.absent,
	       S.slack, gave_up, elapsed, ok);
	return ok ? 0 : 1;
}
