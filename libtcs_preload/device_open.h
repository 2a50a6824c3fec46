/* Opening a scenario's device (device_open.c): by path (open, fopen) or as
 * a CAN socket (socket), each kind of device with its own operations. */
#ifndef TCS_DEVICE_OPEN_H
#define TCS_DEVICE_OPEN_H

#include "runtime.h"

/* The device index of an absolute path, or -1 if it is not a device. */
int tcs_device_lookup(const char *path) TCS_HIDDEN;
/* Opens device dev as open(2) would with oflags: the fd or -errno. */
long tcs_device_open(int dev, int oflags) TCS_HIDDEN;

#endif
