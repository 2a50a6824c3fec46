/* The idioms program: the calls on the pendulum's devices, signals to oneself, semaphores and randomness (calls_world.c). */
#ifndef TCS_IDIOMS_CALLS_WORLD_H
#define TCS_IDIOMS_CALLS_WORLD_H

#include "idioms.h"

void c_dev_read(struct ctx *c);
void c_dev_write(struct ctx *c);
void c_dev_fd(struct ctx *c);
void c_dev_fopen(struct ctx *c);
void sent(struct ctx *c, int seen, int code, const char *what);
void c_kill(struct ctx *c);
void c_raise(struct ctx *c);
void c_sigqueue(struct ctx *c);
void c_tgkill(struct ctx *c);
void c_pidfd_send_signal(struct ctx *c);
int reap(struct ctx *c, pid_t pid);
void exited_zero(struct ctx *c, int st);
void c_kill_child(struct ctx *c);
void c_sem_timedwait(struct ctx *c);
void c_sem_post(struct ctx *c);
void c_cond_timedwait(struct ctx *c);
void c_getrandom(struct ctx *c);
void c_urandom(struct ctx *c);

#endif
