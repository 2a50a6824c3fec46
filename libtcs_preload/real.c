/* The one resolver of the real libc functions (real.h): the next
 * definition of each after this library's, looked up once.
 *
 * Runs as the constructor's first step, single-threaded, or earlier from
 * a hook that another library's constructor called; two threads of such a
 * constructor may resolve at once, and then store the same values. */
#include <dlfcn.h>

#include "real.h"

struct tcs_real_fns tcs_real_fns;
int tcs_real_ready;

#define TCS_RESOLVE(field, name)                                                                               \
	__atomic_store_n(&tcs_real_fns.field, (__typeof__(tcs_real_fns.field))dlsym(RTLD_NEXT, name), \
			 __ATOMIC_RELAXED)
/* A symbol of which libc has several versions: the one named. */
#define TCS_RESOLVE_VERSION(field, name, version)                                                          \
	__atomic_store_n(&tcs_real_fns.field, (__typeof__(tcs_real_fns.field))dlvsym(RTLD_NEXT, name, version), \
			 __ATOMIC_RELAXED)

void tcs_real_resolve(void)
{
	if (__atomic_load_n(&tcs_real_ready, __ATOMIC_ACQUIRE))
		return;
	TCS_RESOLVE(clock_gettime, "clock_gettime");
	TCS_RESOLVE(gettimeofday, "gettimeofday");
	TCS_RESOLVE(fopen, "fopen");
	TCS_RESOLVE(fopen64, "fopen64");
	TCS_RESOLVE(tcgetattr, "tcgetattr");
	TCS_RESOLVE(tcsetattr, "tcsetattr");
	TCS_RESOLVE(if_nametoindex, "if_nametoindex");
	TCS_RESOLVE(if_indextoname, "if_indextoname");
	TCS_RESOLVE(fork, "fork");
	TCS_RESOLVE(posix_spawn, "posix_spawn");
	TCS_RESOLVE(posix_spawnp, "posix_spawnp");
	TCS_RESOLVE(system, "system");
	TCS_RESOLVE(pthread_create, "pthread_create");
	TCS_RESOLVE(pthread_kill, "pthread_kill");
	TCS_RESOLVE(pthread_sigqueue, "pthread_sigqueue");
	TCS_RESOLVE(pthread_setaffinity_np, "pthread_setaffinity_np");
	TCS_RESOLVE(pthread_setschedparam, "pthread_setschedparam");
	TCS_RESOLVE(pthread_setschedprio, "pthread_setschedprio");
	TCS_RESOLVE(timer_create, "timer_create");
	TCS_RESOLVE(timer_settime, "timer_settime");
	TCS_RESOLVE(timer_gettime, "timer_gettime");
	TCS_RESOLVE(timer_getoverrun, "timer_getoverrun");
	TCS_RESOLVE(timer_delete, "timer_delete");
#if defined(__x86_64__)
	/* The condition variables of glibc 2.3.2 on, and those of before,
	 * which it keeps for old binaries (hooks_sync.c hooks both). */
	TCS_RESOLVE_VERSION(pthread_cond_signal, "pthread_cond_signal", "GLIBC_2.3.2");
	TCS_RESOLVE_VERSION(pthread_cond_broadcast, "pthread_cond_broadcast", "GLIBC_2.3.2");
	TCS_RESOLVE_VERSION(pthread_cond_wait, "pthread_cond_wait", "GLIBC_2.3.2");
	TCS_RESOLVE_VERSION(pthread_cond_timedwait, "pthread_cond_timedwait", "GLIBC_2.3.2");
	TCS_RESOLVE_VERSION(pthread_cond_signal_old, "pthread_cond_signal", "GLIBC_2.2.5");
	TCS_RESOLVE_VERSION(pthread_cond_broadcast_old, "pthread_cond_broadcast", "GLIBC_2.2.5");
	TCS_RESOLVE_VERSION(pthread_cond_wait_old, "pthread_cond_wait", "GLIBC_2.2.5");
	TCS_RESOLVE_VERSION(pthread_cond_timedwait_old, "pthread_cond_timedwait", "GLIBC_2.2.5");
#else
	TCS_RESOLVE(pthread_cond_signal, "pthread_cond_signal");
	TCS_RESOLVE(pthread_cond_broadcast, "pthread_cond_broadcast");
	TCS_RESOLVE(pthread_cond_wait, "pthread_cond_wait");
	TCS_RESOLVE(pthread_cond_timedwait, "pthread_cond_timedwait");
#endif
	TCS_RESOLVE(pthread_cond_clockwait, "pthread_cond_clockwait");
	TCS_RESOLVE(pthread_mutex_lock, "pthread_mutex_lock");
	TCS_RESOLVE(pthread_mutex_unlock, "pthread_mutex_unlock");
	TCS_RESOLVE(pthread_mutex_trylock, "pthread_mutex_trylock");
	TCS_RESOLVE(pthread_mutex_timedlock, "pthread_mutex_timedlock");
	TCS_RESOLVE(pthread_mutex_clocklock, "pthread_mutex_clocklock");
	TCS_RESOLVE(sem_wait, "sem_wait");
	TCS_RESOLVE(sem_trywait, "sem_trywait");
	TCS_RESOLVE(sem_post, "sem_post");
	TCS_RESOLVE(sem_timedwait, "sem_timedwait");
	TCS_RESOLVE(sem_clockwait, "sem_clockwait");
	__atomic_store_n(&tcs_real_ready, 1, __ATOMIC_RELEASE);
}
