/* close_all: closes every descriptor it might have, the three ways daemons
 * do, then still sleeps in virtual time and prints how long it slept. */
#include <stdio.h>
#include <time.h>
#include <unistd.h>

int main(void)
{
	for (int fd = 3; fd < 65536; fd++)
		close(fd);
	close_range(3, ~0U, 0);
	closefrom(3);
	for (int fd = 3; fd < 1024; fd++)
		if (dup2(2, fd) >= 0)
			close(fd);
	struct timespec a, b;
	clock_gettime(CLOCK_MONOTONIC, &a);
	sleep(2);
	usleep(500000);
	clock_gettime(CLOCK_MONOTONIC, &b);
	printf("slept_ns=%lld\n", (b.tv_sec - a.tv_sec) * 1000000000LL + (b.tv_nsec - a.tv_nsec));
	return 0;
}
