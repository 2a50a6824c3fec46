/* Actuator writes without a round trip in lockstep (lazy_writes.c). */
#ifndef TCS_PRELOAD_LAZY_WRITES_H
#define TCS_PRELOAD_LAZY_WRITES_H

#include <stddef.h>

#include "runtime.h"

/* Before writing n bytes of buf to device handle h (e: its table entry):
 * 1 if they go without a round trip (then, once all were written,
 * tcs_lazy_write_done), 0 if the write takes the round trip. */
int tcs_lazy_write_begin(int h, const struct tcs_device_entry *e, const void *buf, size_t n) TCS_HIDDEN;
void tcs_lazy_write_done(int h, size_t n) TCS_HIDDEN;
/* A write that takes the round trip: `written` bytes, the last one `last`. */
void tcs_lazy_note_written(int h, const struct tcs_device_entry *e, long written, char last) TCS_HIDDEN;
/* A new handle; a request went to the coordinator (which took the records). */
void tcs_lazy_device_opened(int handle) TCS_HIDDEN;
void tcs_lazy_request_sent(void) TCS_HIDDEN;

#endif
