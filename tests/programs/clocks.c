/* clocks: sleeps through a fixed schedule, printing every clock a program
 * can read after each sleep (identical across lockstep runs with the same
 * --epoch), then hammers the clocks checking that none ever goes back. */
#include <stdio.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/times.h>
#include <time.h>
#include <unistd.h>

#include "work.h"

struct timeb_abi {
	time_t time;
	unsigned short millitm;
	short timezone;
	short dstflag;
};
int ftime(struct timeb_abi *tb);

int main(void)
{
	static const clockid_t mono[] = { CLOCK_MONOTONIC, CLOCK_MONOTONIC_RAW, CLOCK_MONOTONIC_COARSE, CLOCK_BOOTTIME };
	static const clockid_t real[] = { CLOCK_REALTIME, CLOCK_REALTIME_COARSE, CLOCK_TAI };
	long long mono0 = clock_ns(CLOCK_MONOTONIC);
	for (int i = 0; i < 4; i++) {
		usleep(125000 * (i + 1));
		printf("step %d:", i);
		for (unsigned k = 0; k < sizeof mono / sizeof mono[0]; k++)
			printf(" mono%u=%lld", k, clock_ns(mono[k]) - mono0);
		for (unsigned k = 0; k < sizeof real / sizeof real[0]; k++)
			printf(" real%u=%lld", k, clock_ns(real[k]));
		struct timeval tv;
		gettimeofday(&tv, NULL);
		struct timespec tg;
		timespec_get(&tg, TIME_UTC);
		struct timeb_abi tb;
		ftime(&tb);
		printf(" gettimeofday=%lld.%06ld time=%lld timespec_get=%lld.%09ld ftime=%lld.%03u\n", (long long)tv.tv_sec,
		       (long)tv.tv_usec, (long long)time(NULL), (long long)tg.tv_sec, tg.tv_nsec, (long long)tb.time,
		       tb.millitm);
	}
	/* Never backwards, across computation, sleeps and preemption. */
	long long last[3] = { 0, 0, 0 }, backwards = 0;
	for (int i = 0; i < 200000; i++) {
		long long v[3] = { clock_ns(CLOCK_MONOTONIC), clock_ns(CLOCK_REALTIME), clock_ns(CLOCK_PROCESS_CPUTIME_ID) };
		for (int k = 0; k < 3; k++) {
			backwards += v[k] < last[k];
			last[k] = v[k];
		}
		work(50);
		if (i % 1000 == 0)
			usleep(100);
	}
	/* The CPU, by every interface, in this order (each read later than
	 * the one before), and as the kernel charged it before and after. */
	long long kernel_before = kernel_cpu_ns();
	struct tms t;
	times(&t);
	struct rusage ru;
	getrusage(RUSAGE_SELF, &ru);
	long clock_us = (long)clock();
	long long cpu_clock = clock_ns(CLOCK_PROCESS_CPUTIME_ID);
	long long thread_clock = clock_ns(CLOCK_THREAD_CPUTIME_ID);
	long long kernel = kernel_cpu_ns();
	printf("backwards=%lld\n", backwards);
	printf("times_ticks=%lld ticks_per_s=%ld rusage_ns=%lld clock_us=%ld cpu_clock_ns=%lld thread_clock_ns=%lld "
	       "kernel_cpu_ns=%lld kernel_cpu_before_ns=%lld\n",
	       (long long)(t.tms_utime + t.tms_stime), sysconf(_SC_CLK_TCK),
	       ru.ru_utime.tv_sec * 1000000000LL + ru.ru_utime.tv_usec * 1000LL + ru.ru_stime.tv_sec * 1000000000LL +
		       ru.ru_stime.tv_usec * 1000LL,
	       clock_us, cpu_clock, thread_clock, kernel, kernel_before);
	return 0;
}
