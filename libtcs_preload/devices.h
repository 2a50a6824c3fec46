/* Virtual devices in the preload (devices.c): which fds are devices, and
 * their opens, reads, writes and syncs in virtual time. */
#ifndef TCS_DEVICES_H
#define TCS_DEVICES_H

#include <stddef.h>
#include <stdint.h>

#include "runtime.h"

struct iovec;

/* Device fds live below this; the map from fd to device is a flat table. */
#define TCS_DEVICE_FD_MAX 4096

/* The device index of an absolute path, or -1 if it is not a device. */
int tcs_device_lookup(const char *path) TCS_HIDDEN;
/* Opens device dev as open(2) would with oflags: the fd or -errno. */
long tcs_device_open(int dev, int oflags) TCS_HIDDEN;
/* The device handle of fd, or -1 if fd is not a device. */
int tcs_device_handle(int fd) TCS_HIDDEN;
/* The kind of device fd is (enum tcs_device_kind), or 0. */
int tcs_device_kind(int fd) TCS_HIDDEN;
/* How many device fds are open (then readiness checks must sync). */
int tcs_devices_open(void) TCS_HIDDEN;
/* fd was closed / `to` became a copy of `from`. */
void tcs_device_forget(int fd) TCS_HIDDEN;
void tcs_device_copy(int from, int to) TCS_HIDDEN;
/* In a new child, registered: its inherited device fds opened again as its own. */
void tcs_devices_after_fork(void) TCS_HIDDEN;
/* Brings the device up to the controller's virtual time (kind: TCS_SYNC_*;
 * a POLL is for every device, whatever the handle), for a caller already
 * inside tcs_wait_enter(); fd tells whether it is non-blocking. 0 or
 * -errno. */
long tcs_device_sync_held(int handle, int fd, unsigned kind) TCS_HIDDEN;
/* The same, non-blocking or not as told, a wire's read waiting for data
 * until deadline at most (virtual ns; < 0: no deadline). */
long tcs_device_sync_until(int handle, unsigned kind, int nonblock, int64_t deadline) TCS_HIDDEN;
/* read(2), readv(2), write(2), writev(2) of device fd (the runtime active
 * for reads): what is due read in virtual time, what is written taken by
 * the coordinator at the time of the write. The result or -errno. */
long tcs_device_read(int fd, void *buf, size_t n) TCS_HIDDEN;
long tcs_device_readv(int fd, const struct iovec *iov, int n) TCS_HIDDEN;
long tcs_device_write(int fd, const void *buf, size_t n) TCS_HIDDEN;
long tcs_device_writev(int fd, const struct iovec *iov, int n) TCS_HIDDEN;

#endif
