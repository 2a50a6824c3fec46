/* wire_drain TTY BYTES: three times, writes BYTES bytes to the serial
 * line TTY (a [[serial]] of the scenario), waits with tcdrain until the
 * last has left, and sleeps 1 ms. What goes out on a wire is not in a
 * record (docs/DESIGN.md §9), so a replay that writes more is seen to
 * depart only at a request whose time differs. Prints the CLOCK_MONOTONIC
 * reading (ns) just before the first write (write_at), and on stderr a
 * line as each sleep has returned ("wire_drain: slept N"). */
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

int main(int argc, char **argv)
{
	if (argc != 3)
		return 2;
	size_t n = (size_t)atoi(argv[2]);
	char buf[256];
	if (n > sizeof buf)
		return 2;
	memset(buf, 0x55, n);
	int fd = open(argv[1], O_RDWR | O_NOCTTY);
	if (fd < 0) {
		perror(argv[1]);
		return 1;
	}
	long long write_at = 0;
	for (int i = 0; i < 3; i++) {
		struct timespec t;
		clock_gettime(CLOCK_MONOTONIC, &t);
		if (i == 0)
			write_at = t.tv_sec * 1000000000LL + t.tv_nsec;
		if (write(fd, buf, n) != (ssize_t)n)
			perror("write");
		tcdrain(fd);
		struct timespec d = { 0, 1000000 };
		nanosleep(&d, NULL);
		fprintf(stderr, "wire_drain: slept %d\n", i); /* (unbuffered: in order with tcs-run's lines) */
	}
	printf("write_at=%lld\n", write_at);
	return 0;
}
