/* seed_exec: the system's randomness drawn by one process across an exec,
 * for --seed (docs/DESIGN.md §2: the stream goes on across exec; a dup'd
 * random device's fd draws from it as the original does). Prints one
 * key=hex line per draw, in order:
 *   getrandom     getrandom, 8 bytes
 *   dup           read(2) of 8 bytes from a dup of an fd of /dev/urandom
 *   dup2          read(2) of 8 bytes from a dup2 of it to fd 40
 *   after_close   read(2) of 8 bytes from the dup, the original closed
 *   odd           read(2) of 12 bytes from the dup (a block and a half)
 *   readv         readv(2) of 4 + 8 bytes from the dup2
 * then execs itself with "after": getrandom, 8 bytes (exec_getrandom),
 * and getrandom of 3 bytes (exec_short). */
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/random.h>
#include <sys/uio.h>
#include <unistd.h>

static void hex(const char *key, const unsigned char *b, size_t n)
{
	printf("%s=", key);
	for (size_t i = 0; i < n; i++)
		printf("%02x", b[i]);
	printf("\n");
}

static void draw_read(const char *key, int fd, size_t n)
{
	unsigned char b[16] = { 0 };
	if (read(fd, b, n) != (ssize_t)n)
		perror(key);
	hex(key, b, n);
}

int main(int argc, char **argv)
{
	unsigned char b[16] = { 0 };
	if (argc == 2 && strcmp(argv[1], "after") == 0) {
		if (getrandom(b, 8, 0) != 8)
			perror("getrandom");
		hex("exec_getrandom", b, 8);
		if (getrandom(b, 3, 0) != 3)
			perror("getrandom");
		hex("exec_short", b, 3);
		return 0;
	}
	if (getrandom(b, 8, 0) != 8)
		perror("getrandom");
	hex("getrandom", b, 8);
	int fd = open("/dev/urandom", O_RDONLY | O_CLOEXEC);
	int copy = dup(fd);
	draw_read("dup", copy, 8);
	if (dup2(fd, 40) != 40)
		perror("dup2");
	draw_read("dup2", 40, 8);
	close(fd);
	draw_read("after_close", copy, 8);
	draw_read("odd", copy, 12);
	unsigned char v1[4] = { 0 }, v2[8] = { 0 };
	struct iovec iov[2] = { { v1, sizeof v1 }, { v2, sizeof v2 } };
	if (readv(40, iov, 2) != 12)
		perror("readv");
	memcpy(b, v1, 4);
	memcpy(b + 4, v2, 8);
	hex("readv", b, 12);
	fflush(stdout);
	execl("/proc/self/exe", argv[0], "after", (char *)NULL);
	perror("exec");
	return 1;
}
