"""Python's timed waits, each against a known virtual-time answer: Event.wait,
Lock.acquire(timeout=), queue.Queue.get(timeout=), timing out or ended by
another thread. Prints key=value lines: times in ns of time.monotonic, and
for each the process CPU used meanwhile (`_cpu`, ns of the kernel's CPU
clock, kernel_clock.py: not time.process_time, which tcs answers): in cpu
mode a wait is late by no more than that."""
import queue, threading, time

from kernel_clock import kernel_cpu_ns

def timed(fn):
    c = kernel_cpu_ns()
    s = time.monotonic_ns()
    r = fn()
    ns = time.monotonic_ns() - s
    return r, ns, kernel_cpu_ns() - c

def ended_later(ms, end, wait):
    """wait(), which another thread started first ends after ms with end():
    timed from before that thread starts (in cpu mode it may run first)."""
    def run():
        time.sleep(ms / 1000)
        end()
    c = kernel_cpu_ns()
    s = time.monotonic_ns()
    t = threading.Thread(target=run)
    t.start()
    r = wait()
    ns = time.monotonic_ns() - s
    cpu = kernel_cpu_ns() - c
    t.join()
    return r, ns, cpu

ev = threading.Event()
r, ns, cpu = timed(lambda: ev.wait(0.002))
print("event_timeout_result=%d event_timeout_ns=%d event_timeout_cpu=%d" % (r, ns, cpu))
r, ns, cpu = ended_later(1, ev.set, lambda: ev.wait(1))
print("event_set_result=%d event_set_ns=%d event_set_cpu=%d" % (r, ns, cpu))
lock = threading.Lock()
lock.acquire()
r, ns, cpu = timed(lambda: lock.acquire(timeout=0.003))
print("lock_timeout_result=%d lock_timeout_ns=%d lock_timeout_cpu=%d" % (r, ns, cpu))
r, ns, cpu = ended_later(2, lock.release, lambda: lock.acquire(timeout=1))
print("lock_released_result=%d lock_released_ns=%d lock_released_cpu=%d" % (r, ns, cpu))
q = queue.Queue()
def get(timeout):
    try:
        return q.get(timeout=timeout)
    except queue.Empty:
        return "empty"
r, ns, cpu = timed(lambda: get(0.004))
print("queue_timeout_result=%s queue_timeout_ns=%d queue_timeout_cpu=%d" % (r, ns, cpu))
r, ns, cpu = ended_later(1, lambda: q.put("item"), lambda: get(1))
print("queue_put_result=%s queue_put_ns=%d queue_put_cpu=%d" % (r, ns, cpu))
