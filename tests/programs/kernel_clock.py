"""The kernel's CPU clock for Python test programs, read with a system call
instruction of our own (work.h's kernel_clock_ns, for Python): time.
process_time and ctypes' syscall() go through libc, whose calls tcs hooks
and answers with virtual CPU. A test that bounds tcs's charges by this
checks them against the kernel, not against tcs itself."""
import ctypes
import mmap
import platform

CLOCK_PROCESS_CPUTIME_ID = 2

if platform.machine() != "x86_64":
    raise SystemExit("kernel_clock: a raw system call for %s is not written" % platform.machine())

# A system call of two arguments, syscall(nr, a, b) as the C calling
# convention passes them (rdi, rsi, rdx): mov rax, rdi; mov rdi, rsi;
# mov rsi, rdx; syscall; ret.
_CODE = bytes([0x48, 0x89, 0xF8, 0x48, 0x89, 0xF7, 0x48, 0x89, 0xD6, 0x0F, 0x05, 0xC3])
_page = mmap.mmap(-1, mmap.PAGESIZE, prot=mmap.PROT_READ | mmap.PROT_WRITE | mmap.PROT_EXEC)
_page.write(_CODE)
_syscall = ctypes.CFUNCTYPE(ctypes.c_long, ctypes.c_long, ctypes.c_long, ctypes.c_void_p)(
    ctypes.addressof(ctypes.c_char.from_buffer(_page)))
SYS_getrusage, SYS_clock_gettime = 98, 228
RUSAGE_CHILDREN = -1


class _Timespec(ctypes.Structure):
    _fields_ = [("tv_sec", ctypes.c_long), ("tv_nsec", ctypes.c_long)]


class _Timeval(ctypes.Structure):
    _fields_ = [("tv_sec", ctypes.c_long), ("tv_usec", ctypes.c_long)]


class _Rusage(ctypes.Structure):
    _fields_ = [("utime", _Timeval), ("stime", _Timeval), ("rest", ctypes.c_long * 14)]


def kernel_cpu_ns():
    """The process's CPU by the kernel's account, in ns."""
    ts = _Timespec()
    if _syscall(SYS_clock_gettime, CLOCK_PROCESS_CPUTIME_ID, ctypes.addressof(ts)) != 0:
        raise OSError("clock_gettime(CLOCK_PROCESS_CPUTIME_ID) failed")
    return ts.tv_sec * 1000000000 + ts.tv_nsec


def _children_usage():
    ru = _Rusage()
    if _syscall(SYS_getrusage, RUSAGE_CHILDREN, ctypes.addressof(ru)) != 0:
        raise OSError("getrusage(RUSAGE_CHILDREN) failed")
    return ru


def kernel_children_cpu_ns():
    """The CPU of the children this process has waited for (user and
    system), by the kernel's account, in ns (to the microsecond)."""
    ru = _children_usage()
    return (ru.utime.tv_sec + ru.stime.tv_sec) * 1000000000 + (ru.utime.tv_usec + ru.stime.tv_usec) * 1000


def kernel_children_voluntary_switches():
    """How many times the children this process has waited for gave up
    their core (ru_nvcsw): their waits, and each stop tcs made of them."""
    return _children_usage().rest[12]
