/* stop_cost [ROUNDS [CORE]]: the CPU a stop charges the process it stops, as
 * the coordinator stops a controller at each preemption. A child computes on
 * one core, writing its own CPU-time clock to shared memory after every
 * reading; the parent, on another core where there is one (both on CORE
 * when given, as tcs-run given one core runs; at SCHED_FIFO
 * where allowed, as the coordinator), stops it with SIGSTOP every 200 us,
 * waits until waitid reports it stopped, reads the child's CPU clock and
 * continues it. What that reading exceeds the child's last own reading by
 * is what the stop cost it (within one reading of its loop). Prints the
 * median and 99th percentile (ns), and what one turn of the child's loop
 * costs (a CPU-clock system call), as key=value lines. */
#include <sched.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static long long now_ns(clockid_t clock)
{
	struct timespec ts;
	clock_gettime(clock, &ts);
	return ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

static void pin(pid_t pid, int core)
{
	cpu_set_t set;
	CPU_ZERO(&set);
	CPU_SET(core, &set);
	sched_setaffinity(pid, sizeof set, &set);
}

static int by_value(const void *a, const void *b)
{
	long long x = *(const long long *)a, y = *(const long long *)b;
	return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
	int rounds = argc > 1 ? atoi(argv[1]) : 2000;
	int one_core = argc > 2 ? atoi(argv[2]) : -1;
	if (rounds < 10 || argc > 3 || (argc > 2 && one_core < 0)) {
		fprintf(stderr, "usage: stop_cost [ROUNDS >= 10 [CORE]]\n");
		return 2;
	}
	/* [0]: the child's last reading of its CPU clock; [1]: its readings. */
	volatile long long *shared = mmap(NULL, 4096, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
	if (shared == MAP_FAILED) {
		perror("stop_cost: mmap");
		return 1;
	}
	int cores = (int)sysconf(_SC_NPROCESSORS_ONLN);
	pid_t child = fork();
	if (child < 0) {
		perror("stop_cost: fork");
		return 1;
	}
	if (child == 0) {
		pin(0, one_core >= 0 ? one_core : cores - 1);
		for (;;) {
			shared[0] = now_ns(CLOCK_PROCESS_CPUTIME_ID);
			shared[1]++;
		}
	}
	pin(0, one_core >= 0 ? one_core : cores > 1 ? 0 : cores - 1);
	struct sched_param low = { .sched_priority = 10 }, high = { .sched_priority = 20 };
	sched_setscheduler(child, SCHED_FIFO, &low);
	sched_setscheduler(0, SCHED_FIFO, &high);
	clockid_t its_clock;
	if (clock_getcpuclockid(child, &its_clock) != 0) {
		kill(child, SIGKILL);
		return 1;
	}
	/* What a turn of its loop costs, undisturbed for 20 ms. */
	long long cpu0 = now_ns(its_clock), reads0 = shared[1];
	struct timespec quiet = { 0, 20000000 };
	nanosleep(&quiet, NULL);
	long long cpu = now_ns(its_clock) - cpu0, reads = shared[1] - reads0;
	long long *costs = calloc((size_t)rounds, sizeof *costs);
	for (int i = 0; i < rounds; i++) {
		struct timespec pause = { 0, 200000 };
		nanosleep(&pause, NULL);
		kill(child, SIGSTOP);
		siginfo_t si;
		waitid(P_PID, (id_t)child, &si, WSTOPPED);
		costs[i] = now_ns(its_clock) - shared[0];
		kill(child, SIGCONT);
	}
	kill(child, SIGKILL);
	waitpid(child, NULL, 0);
	qsort(costs, (size_t)rounds, sizeof *costs, by_value);
	printf("stop_cost_median_ns=%lld\nstop_cost_p99_ns=%lld\nread_ns=%lld\nother_core=%d\n", costs[rounds / 2],
	       costs[rounds * 99 / 100], reads > 0 ? cpu / reads : -1, one_core < 0 && cores > 1);
	return 0;
}
