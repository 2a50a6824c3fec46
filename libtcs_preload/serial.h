/* A serial line's fd in the preload (serial.c): a tty in raw mode whose
 * reads follow VMIN, VTIME and O_NONBLOCK as the kernel's tty layer does,
 * whose line settings (termios, termios2 with BOTHER) are kept here and
 * whose rate and frame go to the coordinator, which times every byte. Its
 * operations (fd_table.h): read, readv (into its first buffer), write,
 * writev, the tty ioctls and the termios calls. */
#ifndef TCS_SERIAL_H
#define TCS_SERIAL_H

#include "fd_table.h"
#include "runtime.h"

extern const struct tcs_fd_ops tcs_serial_ops TCS_HIDDEN;

#endif
