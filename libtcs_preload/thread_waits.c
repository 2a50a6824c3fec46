/* This thread's waits (thread_waits.h): two counters per thread, which
 * only the thread itself (or a handler on it) reads and writes. */
#include "thread_waits.h"

#include "report.h"
#include "thread_channels.h"

__thread int tcs_in_wait;
__thread int tcs_spun;

int tcs_wait_enter(void)
{
	if (!tcs_active())
		return 0;
	if (tcs_my_channel() < 0) {
		static int once;
		tcs_report_once(&once, "a thread could not get a channel to the coordinator (out of file descriptors?); "
				       "its waits run in real time");
		return 0;
	}
	tcs_in_wait++;
	return 1;
}

void tcs_wait_leave(void)
{
	tcs_in_wait--;
}

void tcs_spin_waited(void)
{
	tcs_spun = 0;
}
