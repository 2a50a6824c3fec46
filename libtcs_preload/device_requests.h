/* A device's two requests to the coordinator (device_requests.c): opening
 * it (DEV_OPEN, whose answer is the fd) and bringing it up to the
 * controller's virtual time (DEV_SYNC). What every kind of device (records,
 * wires) shares, below them. */
#ifndef TCS_DEVICE_REQUESTS_H
#define TCS_DEVICE_REQUESTS_H

#include <stdint.h>

#include "fd_table.h"
#include "runtime.h"

/* Opens device dev as open(2) would with oflags (the access mode already
 * checked): the fd, below TCS_FD_MAX, with the coordinator's handle in
 * *handle; or -errno. The fd is not in the fd table yet. */
long tcs_device_request_open(unsigned dev, int oflags, int *handle) TCS_HIDDEN;
/* Brings the device up to the controller's virtual time (kind: TCS_SYNC_*;
 * a POLL is for every device, whatever the handle), for a caller already
 * inside tcs_wait_enter(); fd tells whether it is non-blocking. 0 or
 * -errno. */
long tcs_device_sync_held(int handle, int fd, unsigned kind) TCS_HIDDEN;
/* The same, non-blocking or not as told, a wire's read waiting for data
 * until deadline at most (virtual ns; < 0: no deadline). */
long tcs_device_sync_until(int handle, unsigned kind, int nonblock, int64_t deadline) TCS_HIDDEN;
/* The same, entering the hook's wait itself. */
long tcs_device_sync(int handle, int fd, unsigned kind) TCS_HIDDEN;
/* Every device kind's after_fork (struct tcs_fd_ops): the child opens the
 * device again as a controller of its own and puts the new fd in the old
 * one's place (same number, flags and close-on-exec), its kind set up as
 * at an open. One it cannot open again is closed (its reads then fail with
 * EBADF, as they would have). */
void tcs_device_after_fork(int fd, const struct tcs_fd *e) TCS_HIDDEN;

#endif
