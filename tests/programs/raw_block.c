/* raw_block MS: reads CLOCK_MONOTONIC, then sleeps MS milliseconds in a raw
 * nanosleep system call (which no hook sees: to tcs it is neither a wait nor
 * computation), then a tight loop of clock reads for as long again, and
 * prints, as key=value lines, how much its monotonic clock advanced over the
 * raw sleep (and the CPU the kernel charged around that, by its own clock)
 * and whether any read in the loop went backwards. (Not through
 * libc's syscall(): tcs hooks that and sends a sleep to its hook.) Under cpu mode
 * the sleep costs no CPU and so no virtual time: a clock estimated from the
 * TSC (TCS_PAGE_CPU_ESTIMATE) may err by its resync interval, no more. */
#include <stdio.h>
#include <stdlib.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "work.h"

static void kernel_nanosleep(const struct timespec *ts)
{
#if defined(__x86_64__)
	long ret;
	__asm__ __volatile__("syscall" : "=a"(ret) : "a"((long)SYS_nanosleep), "D"(ts), "S"(0L) : "rcx", "r11", "memory");
#elif defined(__aarch64__)
	register long x8 __asm__("x8") = SYS_nanosleep;
	register long x0 __asm__("x0") = (long)ts;
	register long x1 __asm__("x1") = 0;
	__asm__ __volatile__("svc 0" : "+r"(x0) : "r"(x8), "r"(x1) : "memory");
#else
#error "raw_block needs the system call instruction of this architecture"
#endif
}

int main(int argc, char **argv)
{
	if (argc != 2) {
		fprintf(stderr, "usage: raw_block MS\n");
		return 2;
	}
	long ms = atol(argv[1]);
	clock_ns(CLOCK_MONOTONIC); /* (binds it: the first call's cost is the linker's) */
	long long k0 = kernel_cpu_ns(), before = clock_ns(CLOCK_MONOTONIC);
	struct timespec ts = { ms / 1000, ms % 1000 * 1000000L };
	kernel_nanosleep(&ts);
	long long after = clock_ns(CLOCK_MONOTONIC), k1 = kernel_cpu_ns();
	long long last = after, backwards = 0, reads = 0;
	long long cpu0 = clock_ns(CLOCK_PROCESS_CPUTIME_ID);
	while (clock_ns(CLOCK_PROCESS_CPUTIME_ID) - cpu0 < ms * 1000000LL) {
		for (int i = 0; i < 1000; i++) {
			long long now = clock_ns(CLOCK_MONOTONIC);
			backwards += now < last;
			last = now;
			reads++;
		}
	}
	printf("raw_sleep_virtual_ns=%lld\nraw_sleep_kernel_cpu_ns=%lld\nreads=%lld\nbackwards=%lld\n", after - before,
	       k1 - k0, reads, backwards);
	return 0;
}
