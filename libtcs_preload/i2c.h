/* An I2C bus's fd in the preload (i2c.c): i2c-dev's ioctls and plain reads
 * and writes, each a transfer the coordinator runs on the chips at the
 * controller's virtual time; the call returns when the transfer's last
 * bit has gone over the wire at the bus clock. */
#ifndef TCS_I2C_H
#define TCS_I2C_H

#include <stddef.h>

#include "runtime.h"

/* read(2)/write(2) of I2C fd (device handle h): one message to the
 * address I2C_SLAVE set. The result or -errno. */
long tcs_i2c_read(int fd, int h, void *buf, size_t n) TCS_HIDDEN;
long tcs_i2c_write(int fd, int h, const void *buf, size_t n) TCS_HIDDEN;
/* ioctl(2) of I2C fd: I2C_SLAVE(_FORCE), I2C_TENBIT, I2C_FUNCS, I2C_RDWR,
 * I2C_SMBUS, I2C_PEC, I2C_RETRIES, I2C_TIMEOUT; -ENOTTY for others. */
long tcs_i2c_ioctl(int fd, int h, unsigned long request, void *arg) TCS_HIDDEN;

#endif
