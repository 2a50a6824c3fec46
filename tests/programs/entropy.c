/* entropy: the clocks and the system's randomness as a C program meets
 * them, one key=value per line, for --seed and --epoch (docs/DESIGN.md §2):
 * a run that repeats prints the same bytes. Randomness by every way a
 * program asks: getrandom, getentropy, syscall(SYS_getrandom), read(2)
 * of /dev/urandom and /dev/random, fread of /dev/urandom, and getrandom in
 * a forked child and in its parent after. */
#include <fcntl.h>
#include <stdio.h>
#include <sys/random.h>
#include <sys/syscall.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static void hex(const char *key, const unsigned char *b, size_t n)
{
	printf("%s=", key);
	for (size_t i = 0; i < n; i++)
		printf("%02x", b[i]);
	printf("\n");
}

static void read_device(const char *key, const char *path)
{
	unsigned char b[16] = { 0 };
	int fd = open(path, O_RDONLY);
	if (fd < 0 || read(fd, b, sizeof b) != (ssize_t)sizeof b)
		perror(path);
	if (fd >= 0)
		close(fd);
	hex(key, b, sizeof b);
}

int main(void)
{
	struct timespec d = { 0, 10000000 }, t;
	nanosleep(&d, NULL);
	clock_gettime(CLOCK_MONOTONIC, &t);
	printf("monotonic=%lld.%09ld\n", (long long)t.tv_sec, t.tv_nsec);
	clock_gettime(CLOCK_REALTIME, &t);
	printf("realtime=%lld.%09ld\n", (long long)t.tv_sec, t.tv_nsec);
	struct timeval tv;
	gettimeofday(&tv, NULL);
	printf("gettimeofday=%lld.%06ld time=%lld\n", (long long)tv.tv_sec, tv.tv_usec, (long long)time(NULL));

	unsigned char b[16];
	if (getrandom(b, sizeof b, 0) != (ssize_t)sizeof b)
		perror("getrandom");
	hex("getrandom", b, sizeof b);
	if (getentropy(b, sizeof b) != 0)
		perror("getentropy");
	hex("getentropy", b, sizeof b);
	if (syscall(SYS_getrandom, b, sizeof b, 0) != (long)sizeof b)
		perror("syscall");
	hex("syscall_getrandom", b, sizeof b);
	read_device("urandom", "/dev/urandom");
	read_device("random", "/dev/random");
	FILE *f = fopen("/dev/urandom", "rb");
	if (!f || fread(b, 1, sizeof b, f) != sizeof b)
		perror("fopen");
	if (f)
		fclose(f);
	hex("fread_urandom", b, sizeof b);

	fflush(stdout);
	pid_t pid = fork();
	if (pid == 0) {
		getrandom(b, 8, 0);
		hex("child_getrandom", b, 8);
		fflush(stdout);
		_exit(0);
	}
	waitpid(pid, NULL, 0);
	getrandom(b, 8, 0);
	hex("parent_getrandom", b, 8);
	return 0;
}
