/* What the preload says on stderr (report.h). A hook may run anywhere, a
 * signal handler included: a line is put together on the stack and goes
 * out in one raw write, so that lines of several threads do not mix. */
#include "raw_syscall.h"
#include "report.h"

void tcs_say(const char *a, const char *b, const char *c)
{
	char buf[256];
	size_t n = 0;
	for (const char *parts[] = { "tcs: ", a, b, c, "\n" }, **q = parts; q < parts + 5; q++)
		for (const char *ch = *q; ch && *ch && n < sizeof buf; ch++)
			buf[n++] = *ch;
	tcs_sys3(SYS_write, 2, buf, n);
}

void tcs_report_once(int *once, const char *msg)
{
	if (__atomic_exchange_n(once, 1, __ATOMIC_RELAXED) == 0)
		tcs_say(msg, NULL, NULL);
}
