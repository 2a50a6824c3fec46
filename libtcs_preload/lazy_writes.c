/* Actuator writes without a round trip, in lockstep mode. There a
 * controller's virtual time moves only when it waits, so every record it
 * writes between two requests carries the time of the next request: the
 * coordinator takes them then (the page's lazy_handles says from which
 * devices), stamped exactly as a round trip per write would have stamped
 * them. A 1 kHz loop that reads, computes, writes and sleeps then costs one
 * round trip a cycle instead of two.
 *
 * A malformed record must still fail its write with EINVAL, so a write goes
 * this way only when tcs_records_check() vouches for all of it, starts on
 * a record boundary, and nothing else could move the controller's time
 * first (one thread, not asleep, not inside another hook). Anything else
 * takes the round trip, as in cpu mode, where the time of each write
 * counts. */
#include "lazy_writes.h"
#include "tcs/record_check.h"
#include "thread_waits.h"

/* Handles beyond this always take the round trip (one bit each in the page). */
#define TCS_LAZY_HANDLES 64
/* Writes and bytes sent on without a round trip since the last request:
 * bounded well below what a socket's buffer holds, so that a loop that
 * never waits cannot block in write() while the coordinator, which has not
 * been asked, waits too. The kernel charges each write a whole buffer
 * (about 1 KiB for a 9-byte line), so the count matters more than the
 * bytes: the default 208 KiB holds some 160 short writes. */
#define TCS_LAZY_WRITES_MAX 32
#define TCS_LAZY_BYTES_MAX (16 * 1024)

/* Per handle: bytes into an incomplete record the coordinator holds (text:
 * 1 while a line has no newline yet). A write that starts mid-record joins
 * it, and only the coordinator can judge the whole. */
static uint32_t tcs_lazy_partial[TCS_LAZY_HANDLES];
static uint32_t tcs_lazy_bytes, tcs_lazy_writes;

void tcs_lazy_device_opened(int handle)
{
	if (handle >= 0 && handle < TCS_LAZY_HANDLES)
		tcs_lazy_partial[handle] = 0;
}

void tcs_lazy_request_sent(void)
{
	tcs_lazy_bytes = 0;
	tcs_lazy_writes = 0;
}

int tcs_lazy_write_begin(int h, const struct tcs_device_entry *e, const void *buf, size_t n)
{
	const struct tcs_clock_page *p = tcs_rt.page;
	if (h < 0 || h >= TCS_LAZY_HANDLES || !tcs_active() || tcs_in_wait || p->mode != TCS_MODE_LOCKSTEP ||
	    (__atomic_load_n(&p->flags, __ATOMIC_RELAXED) & (TCS_PAGE_ASLEEP | TCS_PAGE_REPLAY)) ||
	    __atomic_load_n(&p->threads_started, __ATOMIC_RELAXED) != 0 || tcs_lazy_partial[h] != 0 ||
	    tcs_lazy_writes >= TCS_LAZY_WRITES_MAX || n > TCS_LAZY_BYTES_MAX - tcs_lazy_bytes)
		return 0;
	if (tcs_records_check(buf, n, e->format, e->width) <= 0)
		return 0;
	/* Marked before the bytes go: a signal handler's request in between
	 * takes what is there by then, at the time it was written. */
	__atomic_or_fetch(&tcs_rt.page->lazy_handles, 1ull << h, __ATOMIC_RELEASE);
	return 1;
}

void tcs_lazy_write_done(int h, size_t n)
{
	/* Again: a handler's request between the mark and the write took it. */
	__atomic_or_fetch(&tcs_rt.page->lazy_handles, 1ull << h, __ATOMIC_RELEASE);
	tcs_lazy_bytes += (uint32_t)n;
	tcs_lazy_writes++;
}

void tcs_lazy_note_written(int h, const struct tcs_device_entry *e, long written, char last)
{
	if (h < 0 || h >= TCS_LAZY_HANDLES || written <= 0)
		return;
	if (e->format == TCS_FORMAT_BINARY)
		tcs_lazy_partial[h] = (uint32_t)((tcs_lazy_partial[h] + (uint64_t)written) % (8 * (uint64_t)(e->width ? e->width : 1)));
	else
		tcs_lazy_partial[h] = last != '\n';
}
