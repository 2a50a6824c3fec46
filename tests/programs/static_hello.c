/* static_hello [SECONDS]: linked statically, so tcs's preload never loads
 * in it: tcs-run must refuse it rather than run it in real time, and a
 * controller that starts it must hear that it runs in real time. Sleeps
 * SECONDS (real ones) after saying hello. */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

int main(int argc, char **argv)
{
	puts("hello from a static binary");
	fflush(stdout);
	if (argc > 1) {
		double s = atof(argv[1]);
		struct timespec ts = { (time_t)s, (long)((s - (time_t)s) * 1e9) };
		nanosleep(&ts, NULL);
	}
	return 0;
}
