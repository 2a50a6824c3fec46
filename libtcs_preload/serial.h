/* A serial line's fd in the preload (serial.c): a tty in raw mode whose
 * reads follow VMIN, VTIME and O_NONBLOCK as the kernel's tty layer does,
 * whose line settings (termios, termios2 with BOTHER) are kept here and
 * whose rate and frame go to the coordinator, which times every byte. */
#ifndef TCS_SERIAL_H
#define TCS_SERIAL_H

#include <stddef.h>
#include <termios.h>

#include "runtime.h"
#include "wire_fds.h"

/* A new serial fd's line: raw, 8N1, VMIN 1, at baud. */
void tcs_serial_opened(struct tcs_wire_fd *w, uint32_t baud) TCS_HIDDEN;
/* read(2)/write(2) of serial fd (device handle h): the result or -errno. */
long tcs_serial_read(int fd, int h, void *buf, size_t n) TCS_HIDDEN;
long tcs_serial_write(int fd, int h, const void *buf, size_t n) TCS_HIDDEN;
/* tcgetattr, tcsetattr, tcflush, tcdrain: 0 or -errno. */
long tcs_serial_getattr(int fd, struct termios *t) TCS_HIDDEN;
long tcs_serial_setattr(int fd, int h, const struct termios *t) TCS_HIDDEN;
long tcs_serial_flush(int fd, int h, int queue) TCS_HIDDEN;
long tcs_serial_drain(int fd, int h) TCS_HIDDEN;
/* ioctl(2) of serial fd: the tty requests; -ENOTTY for others. */
long tcs_serial_ioctl(int fd, int h, unsigned long request, void *arg) TCS_HIDDEN;

#endif
