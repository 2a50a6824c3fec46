/* This process as a descendant of a controller (child.c): a new child
 * registering with the coordinator, or one running detached. */
#ifndef TCS_PRELOAD_CHILD_H
#define TCS_PRELOAD_CHILD_H

#include "runtime.h"

/* A new child: registers with the coordinator through parent_channel
 * (fork_v: the parent's virtual time at the fork, when v_known) and takes
 * its own channel and clock page in place of its parent's; 0, or -1 when
 * refused (it then runs in real time). */
int tcs_become_child(int parent_channel, int64_t fork_v, int v_known) TCS_HIDDEN;
/* Start-up: the fork handlers, by which a forked child registers. */
void tcs_child_init(void) TCS_HIDDEN;
/* Says once per process that this descendant runs in real time (page: the
 * clock page it inherited, which remembers who was told; may be NULL). */
void tcs_tell_detached(struct tcs_clock_page *page) TCS_HIDDEN;
/* Start-up of a descendant with no clock page of its own: detached. */
void tcs_detach_descendant(int page_fd) TCS_HIDDEN;

#endif
