/* What of the timerfd hooks (hooks_timerfd.c) the read hook (hooks_io.c)
 * calls: a timerfd's read is served by its own hook file. */
#ifndef TCS_PRELOAD_HOOKS_TIMERFD_H
#define TCS_PRELOAD_HOOKS_TIMERFD_H

#include <stddef.h>

#include "runtime.h"

/* read(2) on a virtual timerfd: the expiration count, or -errno. */
long tcs_timerfd_read(int fd, void *buf, size_t n) TCS_HIDDEN;

#endif
