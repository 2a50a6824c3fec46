/* timerfd_limit: creates timerfds until 66 exist or creation fails twice,
 * as a program with many timers might. Prints key=value lines: how many
 * were made (created), errno's name at the first and second refusal
 * (first_refusal, second_refusal: "none" if there was none), whether one
 * more can be made after one is closed (after_close: ok or the errno), and
 * that timerfd's first expiry: armed for 2 ms, its read's count and span
 * on CLOCK_MONOTONIC (expirations, expiry_ns). */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <sys/timerfd.h>
#include <time.h>
#include <unistd.h>

static long long mono(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec * 1000000000LL + t.tv_nsec;
}

static const char *errno_name(int e)
{
	return e == EMFILE ? "EMFILE" : e == ENFILE ? "ENFILE" : e == ENOMEM ? "ENOMEM" : "other";
}

int main(void)
{
	int fds[66], created = 0;
	const char *refusal[2] = { "none", "none" };
	int refused = 0;
	while (created < 66 && refused < 2) {
		int fd = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC);
		if (fd < 0)
			refusal[refused++] = errno_name(errno);
		else
			fds[created++] = fd;
	}
	printf("created=%d\nfirst_refusal=%s\nsecond_refusal=%s\n", created, refusal[0], refusal[1]);
	close(fds[0]);
	int fd = timerfd_create(CLOCK_MONOTONIC, 0);
	printf("after_close=%s\n", fd >= 0 ? "ok" : errno_name(errno));
	if (fd < 0)
		return 1;
	struct itimerspec its = { { 0, 0 }, { 0, 2000000 } };
	long long t0 = mono();
	timerfd_settime(fd, 0, &its, NULL);
	uint64_t count = 0;
	(void)!read(fd, &count, sizeof count);
	printf("expirations=%llu\nexpiry_ns=%lld\n", (unsigned long long)count, mono() - t0);
	return 0;
}
