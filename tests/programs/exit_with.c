/* exit_with CODE | segv | abort: ends the way a controller can end. */
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int main(int argc, char **argv)
{
	if (argc != 2)
		return 2;
	usleep(1000); /* be a controller for a moment first */
	if (strcmp(argv[1], "segv") == 0) {
		volatile int *p = NULL;
		return *p;
	}
	if (strcmp(argv[1], "abort") == 0)
		abort();
	return atoi(argv[1]);
}
