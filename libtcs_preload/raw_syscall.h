/* Raw system calls for the preload: they return -errno instead of touching
 * errno, and go straight to the kernel, so a hook can never recurse into
 * another hook (or into a libc wrapper that takes a lock or allocates). */
#ifndef TCS_RAW_SYSCALL_H
#define TCS_RAW_SYSCALL_H

#include <errno.h>
#include <sys/syscall.h>
#include <unistd.h>

#if defined(__x86_64__)
static inline long tcs_raw6(long n, long a, long b, long c, long d, long e, long f)
{
	register long r10 __asm__("r10") = d;
	register long r8 __asm__("r8") = e;
	register long r9 __asm__("r9") = f;
	long ret;
	__asm__ __volatile__("syscall"
			     : "=a"(ret)
			     : "a"(n), "D"(a), "S"(b), "d"(c), "r"(r10), "r"(r8), "r"(r9)
			     : "rcx", "r11", "memory");
	return ret;
}
#elif defined(__aarch64__)
static inline long tcs_raw6(long n, long a, long b, long c, long d, long e, long f)
{
	register long x8 __asm__("x8") = n;
	register long x0 __asm__("x0") = a;
	register long x1 __asm__("x1") = b;
	register long x2 __asm__("x2") = c;
	register long x3 __asm__("x3") = d;
	register long x4 __asm__("x4") = e;
	register long x5 __asm__("x5") = f;
	__asm__ __volatile__("svc 0"
			     : "+r"(x0)
			     : "r"(x8), "r"(x1), "r"(x2), "r"(x3), "r"(x4), "r"(x5)
			     : "memory");
	return x0;
}
#else
/* Portable fallback: libc's syscall(), with errno saved around it. */
static inline long tcs_raw6(long n, long a, long b, long c, long d, long e, long f)
{
	int saved = errno;
	long r = syscall(n, a, b, c, d, e, f);
	if (r == -1) {
		r = -errno;
	}
	errno = saved;
	return r;
}
#endif

#define tcs_sys6(n, a, b, c, d, e, f) \
	tcs_raw6((n), (long)(a), (long)(b), (long)(c), (long)(d), (long)(e), (long)(f))
#define tcs_sys0(n) tcs_sys6((n), 0, 0, 0, 0, 0, 0)
#define tcs_sys1(n, a) tcs_sys6((n), (a), 0, 0, 0, 0, 0)
#define tcs_sys2(n, a, b) tcs_sys6((n), (a), (b), 0, 0, 0, 0)
#define tcs_sys3(n, a, b, c) tcs_sys6((n), (a), (b), (c), 0, 0, 0)
#define tcs_sys4(n, a, b, c, d) tcs_sys6((n), (a), (b), (c), (d), 0, 0)
#define tcs_sys5(n, a, b, c, d, e) tcs_sys6((n), (a), (b), (c), (d), (e), 0)

/* The kernel's sigset size (glibc's sigset_t is larger). */
#define TCS_KERNEL_SIGSET_SIZE 8

#endif
