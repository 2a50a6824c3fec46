/* --seed in the preload (random.c): the process's seeded stream
 * (tcs/random_stream.h) in place of the system's randomness, and which
 * fds are /dev/urandom or /dev/random, whose reads draw from it. */
#ifndef TCS_PRELOAD_RANDOM_H
#define TCS_PRELOAD_RANDOM_H

#include <stddef.h>

#include "fd_table.h"
#include "runtime.h"

/* Whether this process draws from a seeded stream. */
int tcs_seeded(void) TCS_HIDDEN;
/* Fills buf with the next n bytes of the stream. */
void tcs_random_fill(void *buf, size_t n) TCS_HIDDEN;
/* getrandom(2) (seeded or not): bytes filled or -errno. */
long tcs_getrandom(void *buf, size_t n, unsigned flags) TCS_HIDDEN;

/* Whether path is a random device (/dev/urandom, /dev/random). */
int tcs_random_path(const char *path) TCS_HIDDEN;
/* fd is open on a random device, seeded: its reads draw the stream (an
 * entry of the fd table). */
void tcs_random_fd_opened(int fd) TCS_HIDDEN;

#endif
