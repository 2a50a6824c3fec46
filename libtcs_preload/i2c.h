/* An I2C bus's fd in the preload (i2c.c): i2c-dev's ioctls and plain reads
 * and writes, each a transfer the coordinator runs on the chips at the
 * controller's virtual time; the call returns when the transfer's last
 * bit has gone over the wire at the bus clock. Its operations (fd_table.h):
 * read and write (one message to the address I2C_SLAVE set), readv and
 * writev (a message per buffer), the i2c-dev ioctls. */
#ifndef TCS_I2C_H
#define TCS_I2C_H

#include "fd_table.h"
#include "runtime.h"

extern const struct tcs_fd_ops tcs_i2c_ops TCS_HIDDEN;

#endif
