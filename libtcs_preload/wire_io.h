/* Packets to a wire's coordinator end, and the waits of a wire's reads
 * (wire_io.c): what serial.c, i2c.c and can.c share. */
#ifndef TCS_WIRE_IO_H
#define TCS_WIRE_IO_H

#include <stddef.h>
#include <stdint.h>

#include "runtime.h"

/* Sends one packet (tcs/wire_protocol.h) on wire fd and has the coordinator
 * take it, at the controller's virtual time: 0 or -errno (the packet's
 * own, or the write's). */
long tcs_wire_send(int fd, int h, uint32_t type, const void *payload, size_t len) TCS_HIDDEN;
/* Brings what is due on wire fd into it; with wait, waits for it until
 * deadline (virtual ns; < 0: none). 0, -EAGAIN (nothing, and not waiting)
 * or -errno. */
long tcs_wire_sync(int fd, int h, int wait, int64_t deadline) TCS_HIDDEN;

#endif
