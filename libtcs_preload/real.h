/* The real libc functions behind the hooks: one table, filled by one
 * resolver (real.c). A hook that passes a call on to libc takes the
 * function from here and nowhere else. */
#ifndef TCS_PRELOAD_REAL_H
#define TCS_PRELOAD_REAL_H

#include <pthread.h>
#include <sched.h>
#include <semaphore.h>
#include <signal.h>
#include <spawn.h>
#include <sys/time.h>
#include <time.h>

#include "runtime.h"

struct termios;

struct tcs_real_fns {
	/* Clocks: what an inactive hook answers with, and the estimate's
	 * vDSO clock (cpu_estimate.h). */
	int (*clock_gettime)(clockid_t, struct timespec *);
	int (*gettimeofday)(struct timeval *, void *);
	/* Devices: stdio (without <stdio.h>, which hooks do not use) and a
	 * serial port's settings. */
	struct _IO_FILE *(*fopen)(const char *, const char *);
	struct _IO_FILE *(*fopen64)(const char *, const char *);
	int (*tcgetattr)(int, struct termios *);
	int (*tcsetattr)(int, int, const struct termios *);
	/* Network interfaces that are not a scenario's CAN interfaces. */
	unsigned int (*if_nametoindex)(const char *);
	char *(*if_indextoname)(unsigned int, char *);
	/* Processes and threads. */
	pid_t (*fork)(void);
	int (*posix_spawn)(pid_t *, const char *, const posix_spawn_file_actions_t *, const posix_spawnattr_t *,
			   char *const[], char *const[]);
	int (*posix_spawnp)(pid_t *, const char *, const posix_spawn_file_actions_t *, const posix_spawnattr_t *,
			    char *const[], char *const[]);
	int (*system)(const char *);
	int (*pthread_create)(pthread_t *, const pthread_attr_t *, void *(*)(void *), void *);
	int (*pthread_kill)(pthread_t, int);
	int (*pthread_sigqueue)(pthread_t, int, const union sigval);
	/* Priorities and affinity of a thread. */
	int (*pthread_setaffinity_np)(pthread_t, size_t, const cpu_set_t *);
	int (*pthread_setschedparam)(pthread_t, int, const struct sched_param *);
	int (*pthread_setschedprio)(pthread_t, int);
	/* POSIX timers that are not ours. */
	int (*timer_create)(clockid_t, struct sigevent *, timer_t *);
	int (*timer_settime)(timer_t, int, const struct itimerspec *, struct itimerspec *);
	int (*timer_gettime)(timer_t, struct itimerspec *);
	int (*timer_getoverrun)(timer_t);
	int (*timer_delete)(timer_t);
	/* Thread waits: condition variables (on x86-64 in both of glibc's
	 * ABIs, the older as *_old), mutexes, semaphores. */
	int (*pthread_cond_signal)(pthread_cond_t *);
	int (*pthread_cond_broadcast)(pthread_cond_t *);
	int (*pthread_cond_wait)(pthread_cond_t *, pthread_mutex_t *);
	int (*pthread_cond_timedwait)(pthread_cond_t *, pthread_mutex_t *, const struct timespec *);
	int (*pthread_cond_signal_old)(pthread_cond_t *);
	int (*pthread_cond_broadcast_old)(pthread_cond_t *);
	int (*pthread_cond_wait_old)(pthread_cond_t *, pthread_mutex_t *);
	int (*pthread_cond_timedwait_old)(pthread_cond_t *, pthread_mutex_t *, const struct timespec *);
	int (*pthread_cond_clockwait)(pthread_cond_t *, pthread_mutex_t *, clockid_t, const struct timespec *);
	int (*pthread_mutex_lock)(pthread_mutex_t *);
	int (*pthread_mutex_unlock)(pthread_mutex_t *);
	int (*pthread_mutex_trylock)(pthread_mutex_t *);
	int (*pthread_mutex_timedlock)(pthread_mutex_t *, const struct timespec *);
	int (*pthread_mutex_clocklock)(pthread_mutex_t *, clockid_t, const struct timespec *);
	int (*sem_wait)(sem_t *);
	int (*sem_trywait)(sem_t *);
	int (*sem_post)(sem_t *);
	int (*sem_timedwait)(sem_t *, const struct timespec *);
	int (*sem_clockwait)(sem_t *, clockid_t, const struct timespec *);
};

/* The table. Read it directly only where start-up has surely run (the
 * runtime is active) or where a function still missing has a way round
 * (clock_gettime: the kernel); elsewhere through tcs_real(). */
extern struct tcs_real_fns tcs_real_fns TCS_HIDDEN;
/* Non-zero once the whole table is filled. */
extern int tcs_real_ready TCS_HIDDEN;

/* Fills the table (dlsym, once; later calls return at once). The first
 * start-up step; and any hook that runs before it, from another library's
 * constructor (one that opens a configuration file, locks a mutex or
 * starts a thread), calls it itself. Not from a signal handler: dlsym is
 * not async-signal-safe, which is why the clock hooks never call it. */
void tcs_real_resolve(void) TCS_HIDDEN;

static inline const struct tcs_real_fns *tcs_real(void)
{
	if (__builtin_expect(!__atomic_load_n(&tcs_real_ready, __ATOMIC_ACQUIRE), 0))
		tcs_real_resolve();
	return &tcs_real_fns;
}

#endif
