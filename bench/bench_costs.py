"""bench/run.py's figures of single operations, each against a baseline
measured in the same rounds: a clock read, a virtual sleep's round trip, a
step barrier over DDS, the CPU a preemption's stop costs, and a step of the
1000-box world."""

import os
import statistics

from bench_core import row

LIBFAKETIME = "/usr/lib/x86_64-linux-gnu/faketime/libfaketime.so.1"


def clock_reads(b):
    n = 2000000 if b.quick else 10000000
    prog = b.path("bench", "clock_cost")
    makers = [
        ("native", lambda: b.values([prog, n])["clock_gettime_ns"]),
        ("cpu", lambda: b.values(b.tcs("-q", prog, n))["clock_gettime_ns"]),
        ("lockstep", lambda: b.values(b.tcs("-q", "-m", "lockstep", prog, n))["clock_gettime_ns"]),
    ]
    if os.path.exists(LIBFAKETIME):
        makers.append(("libfaketime", lambda: b.values([prog, n], env={"LD_PRELOAD": LIBFAKETIME,
                                                                        "FAKETIME": "+0"})["clock_gettime_ns"]))
    m, _ = b.interleaved(makers)
    rows = []
    for mode in ("cpu", "lockstep"):
        rows.append(row("clock_gettime(CLOCK_MONOTONIC), %s mode" % mode, m[mode], "ns", m["native"],
                        "native vDSO call", m[mode] / m["native"], "<= 1.0x native", m[mode] <= m["native"]))
        if "libfaketime" in m:
            rows.append(row("clock_gettime(CLOCK_MONOTONIC), %s mode" % mode, m[mode], "ns", m["libfaketime"],
                            "libfaketime (Debian)", m[mode] / m["libfaketime"], "< 1.0x libfaketime",
                            m[mode] < m["libfaketime"]))
    if "libfaketime" not in m:
        rows.append(row("clock_gettime vs libfaketime", None, "ns", None, "libfaketime (Debian)", None,
                        "< 1.0x libfaketime", None, "libfaketime not installed (apt-get install faketime)"))
    return rows


def sleep_round_trip(b):
    n = 20000 if b.quick else 100000
    pingpong = b.path("bench", "seqpacket_pingpong")
    m, _ = b.interleaved([
        ("pingpong", lambda: b.values([pingpong, n])["seqpacket_roundtrip_ns"]),
        ("event_loop", lambda: b.values([pingpong, n, "--event-loop"])["seqpacket_roundtrip_ns"]),
        ("tcs", lambda: b.values(b.tcs("-q", "-m", "lockstep", b.path("bench", "sleep_roundtrip"), n))
         ["sleep_roundtrip_ns"]),
    ])
    return [row("virtual sleep round trip, lockstep", m["tcs"], "ns", m["pingpong"],
                "same-core SOCK_SEQPACKET ping-pong", m["tcs"] / m["pingpong"], "<= 1.5x",
                m["tcs"] <= 1.5 * m["pingpong"], "world: the built-in pendulum, stepped once per 1000 sleeps"),
            row("same, against the ping-pong with tcs's system calls", m["tcs"], "ns", m["event_loop"],
                "ping-pong + epoll_wait", m["tcs"] / m["event_loop"], "\u2014", None,
                "what tcs's own code costs beyond the system calls it needs")]


def stop_cost(b):
    """The CPU a stop charges the process it stops (bench/stop_cost.c): the
    kernel counts it as the process's, so tcs charges it to the controller
    at each preemption (docs/DESIGN.md, "Preemption and accounting"). Against
    the turn of the stopped program's loop, a CPU-clock system call."""
    rounds = 500 if b.quick else 2000
    medians, p99s, reads, other = [], [], [], 0.0
    for _ in range(b.rounds):
        v = b.values([b.path("bench", "stop_cost"), rounds])
        medians.append(v["stop_cost_median_ns"] / 1e3)
        p99s.append(v["stop_cost_p99_ns"] / 1e3)
        reads.append(v["read_ns"] / 1e3)
        other = v["other_core"]
    median, read = statistics.median(medians), statistics.median(reads)
    return [row("CPU a preemption's stop charges the stopped process", median, "us", read,
                "a CPU-clock read (system call)", median / read, "\u2014", None,
                "p99 %.0f us; stopped from %s" % (statistics.median(p99s), "another core" if other else "its core"))]


def dds_barrier(b):
    """One step barrier with a remote agent: StepGrant out, StepDone back,
    over Cyclone DDS between two processes on loopback; against the same
    ping-pong floor as the sleep round trip, in the same rounds."""
    prog = b.path("bench", "dds_barrier")
    if not os.path.exists(prog):
        return [row("step barrier over DDS (loopback)", None, "us", None, "", None, "\u2014", None,
                    "bench/dds_barrier not built")]
    n = 20000 if b.quick else 100000
    barriers = 2000 if b.quick else 5000
    p99s = []

    def barrier():
        v = b.values([prog, "--rounds", barriers])
        p99s.append(v["p99_us"])
        return v["median_us"]

    m, _ = b.interleaved([
        ("pingpong", lambda: b.values([b.path("bench", "seqpacket_pingpong"), n])["seqpacket_roundtrip_ns"]),
        ("dds", barrier),
    ])
    median, p99, pingpong = m["dds"], statistics.median(p99s), m["pingpong"] / 1e3
    return [row("step barrier over DDS (loopback)", median, "us", pingpong,
                "same-core SOCK_SEQPACKET ping-pong", median / pingpong, "\u2014", None,
                "median of %d runs of %d barriers (4 signals, 1 command, one core); p99 %.0f us; "
                "a 1 ms step world with one agent: at most %.1fx real time" % (b.rounds, barriers, p99, 1e3 / median))]


def box_world(b):
    prog = b.path("bench", "ode_boxes_ratio")
    if not os.path.exists(prog):
        return [row("simhost step, 1000 boxes", None, "us", None, "plain ODE program", None, "<= 1.05x", None,
                    "bench/ode_boxes_ratio not built")]
    v = b.values([prog] + (["--steps", "600", "--rounds", "2"] if b.quick else []))
    tcs_us, plain_us = v["simhost_step_ns_median"] / 1e3, v["plain_step_ns_median"] / 1e3
    return [row("simhost step, 1000-box world", tcs_us, "us", plain_us, "the same world, plain ODE program",
                v["ratio"], "<= 1.05x", v["ratio"] <= 1.05,
                "same state bit for bit" if v.get("same_state") == 1 else "STATES DIFFER")]
