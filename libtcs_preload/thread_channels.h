/* The channels of a controller's threads (thread_channels.c): the main
 * thread waits on the controller's, every other one on its own. */
#ifndef TCS_PRELOAD_THREAD_CHANNELS_H
#define TCS_PRELOAD_THREAD_CHANNELS_H

#include "runtime.h"

/* This thread's channel (made at its first wait), or -errno. */
int tcs_my_channel(void) TCS_HIDDEN;
/* Whether fd is the channel of a thread other than the main one; those
 * channels (at most max, into out): how many. */
int tcs_is_thread_channel(int fd) TCS_HIDDEN;
int tcs_thread_channels(int *out, int max) TCS_HIDDEN;
/* Start-up: the key whose destructor closes an ending thread's channel. */
void tcs_thread_channels_init(void) TCS_HIDDEN;
/* In a forked child: the other threads' channels are not its own. */
void tcs_thread_channels_after_fork(void) TCS_HIDDEN;

/* The fds the runtime owns: a program may not close or replace them. */
static inline int tcs_is_runtime_fd(int fd)
{
	return fd >= 0 && (fd == tcs_rt.channel_fd || fd == tcs_rt.page_fd || tcs_is_thread_channel(fd));
}

#endif
