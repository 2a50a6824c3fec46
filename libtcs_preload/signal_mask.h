/* Signal-masked sections of the runtime: whatever must not be cut in two
 * by a signal handler that may itself call a hook (a lock held, a request
 * on its way, an answer being taken) runs with every signal blocked. Two
 * system calls, only where a lock or the channel is used, never on a clock
 * read. */
#ifndef TCS_PRELOAD_SIGNAL_MASK_H
#define TCS_PRELOAD_SIGNAL_MASK_H

#include <signal.h>
#include <stdint.h>

#include "raw_syscall.h"

/* Blocks every signal (SIGKILL and SIGSTOP stay as they are); the mask
 * before, for tcs_signals_restore. */
static inline uint64_t tcs_signals_block(void)
{
	uint64_t all = ~0ull, old = 0;
	tcs_sys4(SYS_rt_sigprocmask, SIG_BLOCK, &all, &old, TCS_KERNEL_SIGSET_SIZE);
	return old;
}

static inline void tcs_signals_restore(uint64_t old)
{
	tcs_sys4(SYS_rt_sigprocmask, SIG_SETMASK, &old, NULL, TCS_KERNEL_SIGSET_SIZE);
}

#endif
