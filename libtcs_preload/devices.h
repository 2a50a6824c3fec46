/* Virtual devices in the preload: see devices.c. */
#ifndef TCS_DEVICES_H
#define TCS_DEVICES_H

#include <stddef.h>

#include "runtime.h"

/* Device fds live below this; the map from fd to device is a flat table. */
#define TCS_DEVICE_FD_MAX 4096

/* The device index of an absolute path, or -1 if it is not a device. */
int tcs_device_lookup(const char *path) TCS_HIDDEN;
/* Opens device dev as open(2) would with oflags: the fd or -errno. */
long tcs_device_open(int dev, int oflags) TCS_HIDDEN;
/* The device handle of fd, or -1 if fd is not a device. */
int tcs_device_handle(int fd) TCS_HIDDEN;
/* The kind of device fd is (TCS_DEVICE_SENSOR/ACTUATOR), or 0. */
int tcs_device_kind(int fd) TCS_HIDDEN;
/* Whether fd is a stream sensor, whose records in the fd are all due. */
int tcs_device_streams(int fd) TCS_HIDDEN;
/* The table entry of the device fd is (a device fd only). */
const struct tcs_device_entry *tcs_device_entry(int fd) TCS_HIDDEN;
/* How many device fds are open (then readiness checks must sync). */
int tcs_devices_open(void) TCS_HIDDEN;
/* fd was closed / `to` became a copy of `from`. */
void tcs_device_forget(int fd) TCS_HIDDEN;
void tcs_device_copy(int from, int to) TCS_HIDDEN;
/* In a new child, registered: its inherited device fds opened again as its own. */
void tcs_devices_after_fork(void) TCS_HIDDEN;
/* Brings the device up to the controller's virtual time (kind: TCS_SYNC_*);
 * fd tells whether it is non-blocking. 0 or -errno. */
long tcs_device_sync(int handle, int fd, unsigned kind) TCS_HIDDEN;
/* The same, for a caller already inside tcs_wait_enter(). */
long tcs_device_sync_held(int handle, int fd, unsigned kind) TCS_HIDDEN;

#endif
