/* --seed in the preload (random.c): the process's seeded stream
 * (tcs/random_stream.h) in place of the system's randomness, and which
 * fds are /dev/urandom or /dev/random, whose reads draw from it. */
#ifndef TCS_PRELOAD_RANDOM_H
#define TCS_PRELOAD_RANDOM_H

#include <stddef.h>

#include "runtime.h"

struct iovec;

/* Whether this process draws from a seeded stream. */
int tcs_seeded(void) TCS_HIDDEN;
/* Fills buf with the next n bytes of the stream. */
void tcs_random_fill(void *buf, size_t n) TCS_HIDDEN;
/* getrandom(2) (seeded or not): bytes filled or -errno. */
long tcs_getrandom(void *buf, size_t n, unsigned flags) TCS_HIDDEN;

/* Whether path is a random device (/dev/urandom, /dev/random). */
int tcs_random_path(const char *path) TCS_HIDDEN;
/* fd is open on a random device, seeded: its reads draw the stream. */
void tcs_random_fd_opened(int fd) TCS_HIDDEN;
int tcs_random_fd(int fd) TCS_HIDDEN;
/* fd was closed / `to` became a copy of `from`. */
void tcs_random_forget(int fd) TCS_HIDDEN;
void tcs_random_copy(int from, int to) TCS_HIDDEN;
/* read(2) and readv(2) of such an fd: all that was asked. */
long tcs_random_read(void *buf, size_t n) TCS_HIDDEN;
long tcs_random_readv(const struct iovec *iov, int n) TCS_HIDDEN;

#endif
