#!/usr/bin/env python3
"""The performance suite: every figure of tcs against a baseline measured in
the same run, as a ratio (absolute times mean little on a shared machine).
Runs the benchmark programs of bench/ and the tools of a build, prints one
table (figure, tcs, baseline, ratio, target) and writes it as JSON.

    bench/run.py [--build DIR] [--json FILE] [--quick] [--only NAME,...]

Nothing here is a test: a figure that misses its target is marked, and the
exit status is 0 all the same (docs/PERFORMANCE.md explains the misses).
The figures are bench_costs.py's (single operations) and bench_runs.py's
(whole runs); this file runs them and describes the machine."""

import argparse
import datetime
import json
import os
import platform
import subprocess
import sys
import time

from bench_core import Bench, row
from bench_costs import box_world, clock_reads, dds_barrier, sleep_round_trip, stop_cost
from bench_runs import (compute_cost, peak_memory, pendulum_speed, pendulum_through_agent, preemption_overshoot,
                        scaling, timing_error, trace_cost)

BENCHES = [("clock", clock_reads), ("sleep", sleep_round_trip), ("stop", stop_cost), ("dds", dds_barrier),
           ("agent", pendulum_through_agent),
           ("pendulum", pendulum_speed),
           ("overshoot", preemption_overshoot), ("compute", compute_cost), ("error", timing_error), ("boxes", box_world),
           ("memory", peak_memory), ("trace", trace_cost), ("scaling", scaling)]


def first_line(path, default=""):
    try:
        with open(path) as f:
            return f.readline().strip()
    except OSError:
        return default


def machine(b):
    """The facts that decide tcs's speed: the CPU and what it says of its
    TSC, the kernel's clocksource, the cost of a CPU-clock system call
    against a vDSO clock read, the same-core ping-pong, and which clock
    tcs-run chose for cpu-mode estimates (coordinator/realtime.cc)."""
    cpuinfo = open("/proc/cpuinfo").read() if os.path.exists("/proc/cpuinfo") else ""
    model = next((l.split(":", 1)[1].strip() for l in cpuinfo.splitlines() if l.startswith("model name")), "")
    flags = next((l.split(":", 1)[1].split() for l in cpuinfo.splitlines() if l.startswith("flags")), [])
    virt = subprocess.run(["systemd-detect-virt"], capture_output=True, text=True).stdout.strip() \
        if os.path.exists("/usr/bin/systemd-detect-virt") else ""
    cost = b.path("bench", "clock_cost")
    vdso = min(b.values([cost, 2000000])["clock_gettime_ns"] for _ in range(3))
    cpu_clock = min(b.values([cost, 200000, "cpu"])["clock_gettime_ns"] for _ in range(3))
    pingpong = min(b.values([b.path("bench", "seqpacket_pingpong"), 20000])["seqpacket_roundtrip_ns"]
                   for _ in range(3))
    probe, _ = b.run(b.tcs("-m", "cpu", "--", "true"))
    warned = [l.split("warning: ", 1)[1] for l in probe.stderr.splitlines() if "warning: " in l]
    if "SCHED_FIFO on CPU" not in probe.stderr:
        estimate = "none (no SCHED_FIFO): every cpu-mode clock read is a system call"
    elif any("vDSO clock" in w for w in warned):
        estimate = "the vDSO's CLOCK_MONOTONIC_RAW (%s)" % next(w for w in warned if "vDSO" in w)
    elif any("system call" in w for w in warned):
        estimate = "none: " + next(w for w in warned if "system call" in w)
    else:
        estimate = "the TSC"
    return {"cpu": model, "cores": os.cpu_count(), "kernel": platform.release(),
            "virtualization": virt or "unknown", "date": datetime.datetime.now(datetime.timezone.utc).isoformat(),
            "clocksource": first_line("/sys/devices/system/clocksource/clocksource0/current_clocksource", "unknown"),
            "tsc_flags": [f for f in ("constant_tsc", "nonstop_tsc", "tsc_known_freq", "tsc_reliable", "rdtscp",
                                      "hypervisor") if f in flags],
            "tsc_unstable_boot": "tsc=unstable" in first_line("/proc/cmdline"),
            "vdso_clock_ns": vdso, "cpu_clock_ns": cpu_clock, "pingpong_ns": pingpong, "cpu_estimate": estimate}


def fmt(x, unit=""):
    if x is None:
        return "-"
    if isinstance(x, float):
        return ("%.3g" % x) if abs(x) < 1000 else ("%.0f" % x)
    return str(x)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build", help="the meson build directory (default: build)")
    ap.add_argument("--json", help="where to write the table as JSON (default: BUILD/bench-results.json)")
    ap.add_argument("--quick", action="store_true", help="fewer rounds and shorter runs")
    ap.add_argument("--only", help="comma-separated: " + ",".join(n for n, _ in BENCHES))
    args = ap.parse_args()
    if not os.path.exists(os.path.join(args.build, "tools", "tcs-run")):
        sys.exit("bench/run.py: no tcs-run in %s: build first (meson setup %s && ninja -C %s)" %
                 (args.build, args.build, args.build))
    b = Bench(os.path.abspath(args.build), args.quick)
    only = set(args.only.split(",")) if args.only else None
    info = machine(b)
    print("tcs performance, %s, %s cores, kernel %s (%s), %s" %
          (info["cpu"], info["cores"], info["kernel"], info["virtualization"], info["date"][:19]), flush=True)
    print("  clocksource %s; TSC flags: %s%s" % (info["clocksource"], " ".join(info["tsc_flags"]) or "none",
                                                 "; the boot line says tsc=unstable" if info["tsc_unstable_boot"]
                                                 else ""))
    print("  a CPU-clock read (system call) %.0f ns, a vDSO clock read %.1f ns (%.0fx); same-core ping-pong %.1f us"
          % (info["cpu_clock_ns"], info["vdso_clock_ns"], info["cpu_clock_ns"] / info["vdso_clock_ns"],
             info["pingpong_ns"] / 1e3))
    print("  cpu-mode clock reads estimate the CPU from: %s" % info["cpu_estimate"], flush=True)
    rows = []
    for name, fn in BENCHES:
        if only and name not in only:
            continue
        t0 = time.monotonic()
        print("  running %-10s ..." % name, end="", flush=True, file=sys.stderr)
        try:
            rows += fn(b)
        except Exception as e:  # a benchmark that cannot run is reported, the rest go on
            rows.append(row(name, None, "", None, "", None, "", False, "FAILED: %s" % e))
        print(" %.1f s" % (time.monotonic() - t0), file=sys.stderr, flush=True)
    head = ("figure", "tcs", "unit", "baseline", "ratio", "target", "")
    table = [head] + [(r["figure"], fmt(r["tcs"]), r["unit"], fmt(r["baseline"]) + (" (%s)" % r["baseline_name"]
                                                                                 if r["baseline_name"] else ""),
                       fmt(r["ratio"]), r["target"],
                       {True: "ok", False: "MISSED", None: ""}[r["meets_target"]] +
                       ("  " + r["note"] if r["note"] else "")) for r in rows]
    widths = [max(len(t[i]) for t in table) for i in range(len(head) - 1)]
    for t in table:
        print("  ".join(t[i].ljust(widths[i]) for i in range(len(head) - 1)) + "  " + t[-1])
    out = args.json or os.path.join(args.build, "bench-results.json")
    with open(out, "w") as f:
        json.dump({"machine": info, "quick": args.quick, "rows": rows}, f, indent=1)
    print("written: %s" % out)


if __name__ == "__main__":
    main()
