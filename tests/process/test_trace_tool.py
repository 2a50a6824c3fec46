"""tcs-trace (docs/DESIGN.md §6): its summary checked against runs whose figures
are known in advance (a loop whose work is a fixed amount of its own,
virtualised, CPU time), exports that parse, plots that are images, and a
clear error for every file that is not a readable tcs trace."""

import csv
import io
import json
import math
import os
import struct
import tempfile
import xml.etree.ElementTree as ET

from harness import (AHEAD, READ, TCS_TRACE, check, main, periodic_reports, prog, read_trace, run, scenario_file, stop_cost,
                     tcs)

TMP = tempfile.mkdtemp(prefix="tcs-test-trace-tool-")


def trace_tool(*args, timeout=60, env=None):
    return run([TCS_TRACE] + [str(a) for a in args], timeout=timeout, env=env)


def traced_run(name, *args, timeout=120):
    """Runs tcs-run ARGS with a trace; returns (trace path, tcs-run result)."""
    path = os.path.join(TMP, name + ".mcap")
    r = tcs("-t", path, "--no-slack", *args, timeout=timeout)
    check(r.returncode == 0, "the traced run succeeds", r)
    mcap_counts(path)  # the official reader reads it, message by message
    return path, r


def summary(path):
    r = trace_tool("summary", "--json", path)
    check(r.returncode == 0, "tcs-trace summary --json succeeds", r)
    return json.loads(r.stdout)


def assert_error(r, *words):
    """Exit 2 and one line on stderr that says what is wrong (and, for a
    mistake in the command line, a line pointing at --help)."""
    lines = r.stderr.strip().splitlines()
    check(r.returncode == 2, "exit status 2", r)
    check(lines and lines[0].startswith("tcs-trace: "), "an error line", r)
    check(lines[1:] in ([], ["Try 'tcs-trace --help' for more information."]), "nothing else", r)
    for w in words:
        check(w in lines[0], "the error says %r" % w, r)


_on_time = []


def on_time_trace():
    """A 1 kHz loop doing 300 us of CPU per cycle for 2 s: the program's
    own counts are printed too. Made once, shared by several tests."""
    if not _on_time:
        _on_time.append(traced_run("on-time", "--", prog("periodic"), 1000, 2, "300us"))
    return _on_time[0]


def test_summary_of_a_loop_that_keeps_its_deadlines():
    path, r = on_time_trace()
    own = r.values()
    s = summary(path)
    c = s["controllers"][0]
    print("  %d cycles at %.3f Hz, %d misses, charged %.1f ms, period p50/p99/max %d/%d/%d ns" %
          (c["cycles"], c["rate_hz"], c["deadline_misses"], c["charged_cpu_ns"] / 1e6,
           c["period"]["p50_ns"], c["period"]["p99_ns"], c["period"]["max_ns"]))
    check(not s["truncated"] and c["periodic"], "a complete trace of a periodic loop")
    check(c["cycles"] == int(own["loops"]), "one cycle per loop the program counted (%s)" % own["loops"])
    misses_as_counted(c, own)
    # 300 us of work fits a 1 ms period: the only misses are those a pause
    # of the machine inside the work causes (charged as CPU by the kernel,
    # natively too), which the program counts from the kernel's own clock,
    # not from tcs's (pause_misses: periodic.c).
    check(int(own["misses"]) <= int(own["pause_misses"]),
          "no deadline missed but for pauses of the machine (%s misses; %s rounds paused, explaining %s)" %
          (own["misses"], own["paused_rounds"], own["pause_misses"]))
    check(c["asked_period_ns"] == 1000000, "the period it asked for: 1 ms")
    waits = wakes_on_schedule(path, c, 1000000)
    # Kept, the first and the last wait end at their deadlines, (cycles - 1)
    # periods of 1 ms apart: exactly 1 kHz.
    check(missed(waits[0]) or missed(waits[-1]) or c["rate_hz"] == 1000, "loop rate %.9g Hz" % c["rate_hz"])
    check(c["deadline_misses"] > 0 or c["period"]["min_ns"] == c["period"]["max_ns"] == 1000000,
          "every period 1 ms when none is missed")
    check(int(own["cpu_ns"]) >= c["cycles"] * 300e3, "the program did its 300 us of work in each cycle")
    charged_as_the_program_saw(path, c, own)
    # cpu mode: a slice's virtual time is the CPU it was charged, exactly.
    check(s["timing_error"] == 0, "cpu mode: computing costs exactly the CPU charged (%.9g)" % s["timing_error"])
    # The run ends with the program: at the end of its loop by its own clock
    # (its start, a period before its first deadline, and elapsed_s: 2 s or
    # more) and the CPU it was charged after that read (all it was charged
    # less cpu_ns, its last CPU read, after three calls, each under 25 us).
    # Each of those two reads may run ahead by 20 us.
    elapsed = round(float(own["elapsed_s"]) * 1e9)
    end = waits[0]["deadline_ns"] - 1000000 + elapsed + c["charged_cpu_ns"] - int(own["cpu_ns"])
    print("  run ends at %d ns: %+d ns from the end of its loop and its CPU after it; %d steps" %
          (s["virtual_ns"], s["virtual_ns"] - end, s["steps"]))
    check(elapsed >= 2e9 and end - AHEAD <= s["virtual_ns"] <= end + 3 * READ + AHEAD and s["wall_ns"] > 0,
          "virtual time of the run %d ns: its 2 s loop (%d ns) and its CPU outside it" % (s["virtual_ns"], elapsed))
    # The world steps to each boundary before a wake (no one can run before
    # it: docs/DESIGN.md §2), never past its controller: 1 ms steps from the last
    # wake's to the end's.
    check(waits[-1]["v_end_ns"] // 1000000 <= s["steps"] <= s["virtual_ns"] // 1000000 and
          s["step_wall_cost"]["min_ns"] > 0, "the world's %d steps and their wall cost" % s["steps"])
    text = trace_tool("summary", path)
    verdict = ("MISSED %d of %d deadlines" % (c["deadline_misses"], c["cycles"]) if c["deadline_misses"]
               else "kept every deadline")
    check(text.returncode == 0 and verdict in text.stdout and "1000.0 Hz" in text.stdout,
          "the text summary gives the verdict", text)


def charged_as_the_program_saw(path, c, own):
    """The program last read its CPU clock (own["cpu_ns"]) after its last
    wait: the trace charges it that much by the end of the run, and had
    charged it no more before the slices after that wait (more than one
    when it was preempted on its way out)."""
    e = trace_tool("export", path, "--format", "csv", "--topic", "/tcs/slice")
    slices = [s for s in csv.DictReader(io.StringIO(e.stdout)) if int(s["controller"]) == c["controller"]]
    woke = max(w["v_end_ns"] for w in loop_waits(path, c))
    after = sum(int(s["charged_ns"]) for s in slices if int(s["v_start_ns"]) >= woke)
    seen, total = int(own["cpu_ns"]), c["charged_cpu_ns"]
    check(total - after <= seen <= total,
          "charged CPU %.3f ms (%.3f ms of it after the last wait), %.3f ms when the program last read its CPU "
          "clock" % (total / 1e6, after / 1e6, seen / 1e6))


def slices_end_with_its_exit(path, c):
    """A controller's slices are all there: the last one ends with its
    exit, however that exit came (a check that held it as it exited had
    left the lane first, and two controllers in three lost their last)."""
    e = trace_tool("export", path, "--format", "csv", "--topic", "/tcs/slice")
    slices = [s for s in csv.DictReader(io.StringIO(e.stdout)) if int(s["controller"]) == c["controller"]]
    ends = [s["end"] for s in sorted(slices, key=lambda s: int(s["v_start_ns"]))]
    check(ends and ends[-1] == "exited" and ends.count("exited") == 1,
          "controller %d's slices end with its exit: %s" % (c["controller"], ends[-3:]))


def misses_as_counted(c, own):
    """tcs counts a miss where a wait is asked for after its deadline, the
    program where it checks, just before asking: each miss the program
    counts is tcs's too, and tcs's others are waits whose call's CPU, by
    the kernel's clock, may have crossed the deadline (periodic.c:
    crossed_waits)."""
    m, mine, crossed = c["deadline_misses"], int(own["misses"]), int(own["crossed_waits"])
    check(mine <= m <= mine + crossed, "%d misses in the trace: the program's %d, and up to %d crossed in the call" %
          (m, mine, crossed))


def loop_waits(path, c):
    """The controller's periodic (absolute) waits in the trace, in order."""
    e = trace_tool("export", path, "--format", "csv", "--topic", "/tcs/wait")
    check(e.returncode == 0, "the waits exported", e)
    return [{k: int(w[k]) for k in ("v_request_ns", "deadline_ns", "v_end_ns")}
            for w in csv.DictReader(io.StringIO(e.stdout))
            if int(w["controller"]) == c["controller"] and w["absolute"] == "true"]


def missed(w):
    """Asked for a deadline already past (trace_data.h)."""
    return w["deadline_ns"] <= w["v_request_ns"]


def as_in_json(x):
    """x as the summary's JSON writes it: %.0f if integral, else %.9g."""
    return float("%.0f" % x) if x == math.floor(x) else float("%.9g" % x)


def spread(values):
    """The summary's spread of values: nearest-rank percentiles."""
    v = sorted(values)

    def rank(p):
        return v[min(len(v) - 1, math.ceil(p * len(v)) - 1)]
    return {"count": len(v), "min_ns": v[0], "p50_ns": rank(0.5), "p99_ns": rank(0.99), "max_ns": v[-1]}


def wakes_on_schedule(path, c, period):
    """A periodic loop's waits in the trace: each ends at its deadline (tcs
    has no timer slack: docs/DESIGN.md §2), or at once if that is already
    past (a miss), and its deadlines are a period apart. The summary's rate
    is (cycles - 1) over the first to the last wake, its periods those
    between wakes. Returns the waits."""
    waits = loop_waits(path, c)
    check(len(waits) == c["cycles"], "a wait per cycle: %d" % len(waits))
    wrong = [w for w in waits if w["v_end_ns"] != max(w["deadline_ns"], w["v_request_ns"])]
    check(not wrong, "each wait ends at its deadline, at once if that is past: %s" % wrong[:3])
    check(all(b["deadline_ns"] - a["deadline_ns"] == period for a, b in zip(waits, waits[1:])),
          "deadlines %d ns apart" % period)
    wakes = [w["v_end_ns"] for w in waits]
    rate = (len(wakes) - 1) * 1e9 / (wakes[-1] - wakes[0])
    check(c["rate_hz"] == as_in_json(rate), "rate %.9g Hz, that of the wakes: %.9g Hz" % (c["rate_hz"], rate))
    periods = spread([b - a for a, b in zip(wakes, wakes[1:])])
    check(c["period"] == periods, "periods %s, those between the wakes: %s" % (c["period"], periods))
    return waits


def test_summary_of_an_overloaded_loop():
    # 1.5 ms of work per 1 ms period: it runs at 2/3 of its rate and misses
    # every deadline, in cpu mode; lockstep (computation free) hides it.
    path, r = traced_run("overloaded", "--", prog("periodic"), 1000, 2, "1500us")
    own = r.values()
    c = summary(path)["controllers"][0]
    print("  cpu mode: %d cycles at %.2f Hz, %d misses, CPU %.1f %% of %.3f s" %
          (c["cycles"], c["rate_hz"], c["deadline_misses"], 100.0 * c["charged_cpu_ns"] / c["span_ns"],
           c["span_ns"] / 1e9))
    check(c["cycles"] == int(own["loops"]) and c["deadline_misses"] == int(own["misses"]),
          "cycles and misses as the program counted them (%s, %s)" % (own["loops"], own["misses"]))
    # 1.5 ms of work by the kernel's clock in a 1 ms period: the first check
    # is late and the lateness only grows.
    check(c["deadline_misses"] == c["cycles"], "every deadline missed")
    # Each loop is its 1500 us of work and the loop's own calls; tcs charges
    # no more than the kernel did around it (loop_kernel_cpu_ns), less at
    # most what a read runs ahead (20 us) and what the stops tcs made of the
    # work cost (left out).
    loops, loop_cpu = int(own["loops"]), int(own["loop_cpu_ns"])
    stops = int(own["work_stops"]) * stop_cost()
    check(loops * 1.5e6 - AHEAD - stops <= loop_cpu <= int(own["loop_kernel_cpu_ns"]) + AHEAD,
          "%d loops of 1500 us: %d ns charged, the kernel's %s ns" % (loops, loop_cpu, own["loop_kernel_cpu_ns"]))
    wakes_on_schedule(path, c, 1000000)
    # Every wait returns at once (missed), so its time is the CPU charged,
    # from its first slice to its last: it runs at 1/(CPU per loop), its
    # rate (cycles - 1) over the CPU between its first and last wake.
    check(c["charged_cpu_ns"] == c["span_ns"], "busy all the time: %d ns charged in %d ns" %
          (c["charged_cpu_ns"], c["span_ns"]))
    # A period, one loop's CPU, holds its work (a wake's mark may run ahead).
    check(c["period"]["min_ns"] >= 1.5e6 - AHEAD, "each period 1.5 ms of work or more: %s" % c["period"])

    path, r = traced_run("lockstep", "-m", "lockstep", "--spin-cost", "0", "--", prog("periodic"), 1000, 1, "1500us")
    own = r.values()
    s = summary(path)
    c = s["controllers"][0]
    print("  lockstep: %d cycles at %.2f Hz, %d misses, timing error %.1f %%" %
          (c["cycles"], c["rate_hz"], c["deadline_misses"], 100 * s["timing_error"]))
    # Computation is free: every wait ends at its deadline, 1 ms apart, and
    # the loop's 1 s holds exactly 1000.
    check(c["mode"] == "lockstep" and c["deadline_misses"] == 0, "lockstep: no miss")
    check(c["cycles"] == int(own["loops"]) == 1000, "lockstep: 1000 cycles in 1 s (%s)" % own["loops"])
    wakes_on_schedule(path, c, 1000000)
    check(c["rate_hz"] == 1000, "lockstep: the full rate")
    # The CPU is still charged, as in cpu mode (above).
    loops, loop_cpu = int(own["loops"]), int(own["loop_cpu_ns"])
    check(loops * 1.5e6 - AHEAD <= loop_cpu <= int(own["loop_kernel_cpu_ns"]) + AHEAD,
          "lockstep: %d loops of 1500 us: %d ns charged, the kernel's %s ns" %
          (loops, loop_cpu, own["loop_kernel_cpu_ns"]))
    charged_as_the_program_saw(path, c, own)
    # No virtual time passes in any slice: |0 - charged| over charged.
    check(s["timing_error"] == 1, "lockstep: computing took no virtual time at all")


def test_summary_of_preempted_controllers():
    # Two controllers on one core: each is preempted when the other is due.
    # 80 % of the core in all (40 % each, the second on a CPU twice as
    # slow): the rest leaves room for what preemption costs them.
    with scenario_file('''
[sim]
step = "1ms"
model = "pendulum"
[[controller]]
command = "%s 1000 1 400us"
[[controller]]
command = "%s 250 1 1600us 2"
cpu_scale = 2.0
''' % (prog("periodic"), prog("periodic"))) as world:
        path, r = traced_run("two", "-w", world, "-q")
    reports = {p["asked_hz"]: p for p in periodic_reports(r.stdout)}
    fast, slow = reports["1000"], reports["250"]
    s = summary(path)
    check(len(s["controllers"]) == 2, "both controllers")
    a, b = s["controllers"]
    for c in (a, b):
        print("  %s at %.1f Hz: %d misses, %d preemptions, overshoot p50 %d ns, p99 %d ns" %
              (c["name"].split("/")[-1], c["rate_hz"], c["deadline_misses"], c["preemptions"],
               c["overshoot"]["p50_ns"], c["overshoot"]["p99_ns"]))
        check(c["overshoot"]["count"] == c["preemptions"], "an overshoot per preemption")
        check(c["overshoot"]["min_ns"] >= 0, "a preemption comes after the budget, never before")
    check(b["cpu_scale"] == 2.0 and a["cpu_scale"] == 1.0, "each controller's CPU scale")
    check(a["preemptions"] + b["preemptions"] > 0, "controllers were preempted")
    for c, own, period in ((a, fast, 1000000), (b, slow, 4000000)):
        check(c["asked_period_ns"] == period and c["cycles"] == int(own["loops"]),
              "cycles as the program counted them: %s" % own)
        misses_as_counted(c, own)
        slices_end_with_its_exit(path, c)
        waits = wakes_on_schedule(path, c, period)
        # Preempted or not, kept waits end at their deadlines: kept, the
        # first and the last wait make the rate exactly the one asked for.
        check(missed(waits[0]) or missed(waits[-1]) or c["rate_hz"] == 1e9 / period,
              "the %d Hz one keeps its rate: %.9g Hz" % (1e9 / period, c["rate_hz"]))
    # Broken preemption would miss nearly every cycle. The 1 kHz one's
    # 400 us of work fits its period: it misses only where the kernel's CPU
    # explains it (periodic.c: pause_misses).
    check(int(fast["misses"]) <= int(fast["pause_misses"]),
          "the 1 kHz one misses no deadline but for pauses (%s misses, %s explained)" %
          (fast["misses"], fast["pause_misses"]))
    # The 250 Hz one's 1.6 ms of work is 3.2 ms of its 4 ms at scale 2,
    # which it is told: its pause_misses count its rounds at that scale.
    check(int(slow["misses"]) <= int(slow["pause_misses"]),
          "the 250 Hz one misses no deadline but for pauses (%s misses, %s explained)" %
          (slow["misses"], slow["pause_misses"]))
    check(int(slow["cpu_ns"]) >= b["cycles"] * 1.6e6, "1.6 ms of virtual CPU per cycle, at scale 2")
    charged_as_the_program_saw(path, b, slow)


def test_exports_parse():
    path, _ = on_time_trace()
    counts = mcap_counts(path)
    out = os.path.join(TMP, "slices.csv")
    r = trace_tool("export", path, "--format", "csv", "-o", out)
    check(r.returncode == 0, "csv export", r)
    with open(out, newline="") as f:
        rows = list(csv.DictReader(f))
    check(len(rows) == counts["/tcs/slice"], "a row per slice")
    check(all(int(x["v_end_ns"]) >= int(x["v_start_ns"]) for x in rows), "numeric columns")
    check({"blocked"} <= {x["end"] for x in rows}, "the end column")

    r = trace_tool("export", path, "-f", "csv", "--topic", "/tcs/step")
    rows = list(csv.DictReader(io.StringIO(r.stdout)))
    check(r.returncode == 0 and len(rows) == counts["/tcs/step"], "steps to stdout, a row per step", r)
    check("joint.pendulum.hinge.position" in rows[0] and "joint_values[0]" not in rows[0],
          "joint states flattened into a column per joint")

    r = trace_tool("export", path, "-f", "json")
    check(r.returncode == 0, "json export", r)
    doc = json.loads(r.stdout)
    check(len(doc["messages"]) == sum(counts.values()), "every message in the JSON export")
    check({m["topic"] for m in doc["messages"]} == set(counts), "with its topic")

    out = os.path.join(TMP, "trace.json")
    r = trace_tool("export", path, "-f", "chrome", "-o", out)
    check(r.returncode == 0, "chrome export", r)
    with open(out) as f:
        events = json.load(f)["traceEvents"]
    names = {e["args"]["name"] for e in events if e["ph"] == "M" and e["name"] == "thread_name"}
    check("simulation" in names and any(n.startswith("controller 1: ") for n in names),
          "one track per controller and one for the simulation: %s" % names)
    spans = [e for e in events if e["ph"] == "X"]
    check(all(e["dur"] >= 0 and "ts" in e and "tid" in e for e in spans), "complete events")
    check(sum(1 for e in spans if e.get("cat") == "slice") == counts["/tcs/slice"], "every slice")
    check(sum(1 for e in spans if e.get("cat") == "simulation") == counts["/tcs/step"], "every step")
    check(any(e["ph"] == "C" for e in events), "joint states as counters")


def test_plots_are_images():
    path, _ = on_time_trace()
    for kind in ("timing", "disparity", "error", "joints"):
        png = os.path.join(TMP, kind + ".png")
        r = trace_tool("plot", path, "-o", png, "--kind", kind)
        check(r.returncode == 0, "plot %s" % kind, r)
        with open(png, "rb") as f:
            data = f.read()
        check(data[:8] == b"\x89PNG\r\n\x1a\n", "a PNG")
        width, height = struct.unpack(">II", data[16:24])
        check(width >= 600 and height >= 400 and len(data) > 5000, "%s: a real picture, %dx%d, %d bytes" %
              (kind, width, height, len(data)))
        svg = os.path.join(TMP, kind + ".svg")
        r = trace_tool("plot", path, "-o", svg, "-k", kind)
        check(r.returncode == 0, "svg %s" % kind, r)
        root = ET.parse(svg).getroot()
        check(root.tag.endswith("svg") and len(list(root.iter())) > 20, "an SVG with something drawn")
    r = trace_tool("plot", path, "-o", os.path.join(TMP, "x.png"), env={"PATH": "/nonexistent"})
    assert_error(r, "gnuplot not found")


def test_killed_run_is_summarised():
    # A trace cut short in its last chunk (as a SIGKILLed run leaves it) is
    # read as far as it goes: its complete chunks. 6 s of a 1 kHz loop make
    # more than one chunk (of 1 MB of messages).
    path, _ = traced_run("long", "--", prog("periodic"), 1000, 6, "100us")
    with open(path, "rb") as f:
        data = f.read()
    found = chunks(data)
    check(len(found) >= 2, "6 s of trace in more than one chunk", found)
    start, length = found[-1]
    cut = os.path.join(TMP, "cut.mcap")
    with open(cut, "wb") as f:
        f.write(data[:start + length // 2])
    s = summary(cut)
    check(s["truncated"] and 0 < s["controllers"][0]["cycles"] < 6000, "a truncated trace's figures", s)
    text = trace_tool("summary", cut)
    check("not closed" in text.stdout, "the text says the trace was not closed", text)


def test_bad_files_and_usage():
    missing = os.path.join(TMP, "missing.mcap")
    assert_error(trace_tool("summary", missing), missing, "No such file")
    text = os.path.join(TMP, "notes.txt")
    with open(text, "w") as f:
        f.write("not a trace\n")
    assert_error(trace_tool("summary", text), "not an MCAP file")
    assert_error(trace_tool("export", text, "-f", "csv"), "not an MCAP file")

    foreign = os.path.join(TMP, "foreign.mcap")
    with open(foreign, "wb") as f:
        f.write(minimal_mcap())
    assert_error(trace_tool("summary", foreign), "not a tcs trace")

    path, _ = on_time_trace()
    with open(path, "rb") as f:
        data = bytearray(f.read())
    # Bytes changed inside the first chunk: its data no longer decompress
    # or no longer match their CRC.
    start, length = chunks(data)[0]
    for at in (start + length // 3, start + length // 2):
        for i in range(at, at + 16):
            data[i] ^= 0x5A
        bad = os.path.join(TMP, "corrupt.mcap")
        with open(bad, "wb") as f:
            f.write(data)
        assert_error(trace_tool("summary", bad), bad + ": at byte ")
        assert_error(trace_tool("export", bad, "-f", "json"), bad + ": at byte ")

    out = os.path.join(TMP, "never.csv")
    assert_error(trace_tool("export", missing, "-f", "csv", "-o", out), "No such file")
    check(not os.path.exists(out), "a failed export leaves no file behind")
    assert_error(trace_tool("frobnicate", path), "unknown command")
    assert_error(trace_tool("summary"), "no trace file")
    assert_error(trace_tool("plot", path), "-o")
    assert_error(trace_tool("plot", path, "-o", os.path.join(TMP, "x.jpg")), "png or .svg")
    assert_error(trace_tool("plot", path, "-o", os.path.join(TMP, "x.png"), "-k", "pie"), "pie")
    assert_error(trace_tool("export", path), "--format")
    assert_error(trace_tool("export", path, "-f", "xml"), "xml")
    check(trace_tool("--help").stdout.startswith("Usage: tcs-trace"), "--help")


def mcap_counts(path):
    """Messages per topic, as the official reader counts them."""
    return read_trace(path)["topics"]


def chunks(data):
    """(offset, length) of each Chunk record of an MCAP file."""
    at, found = 8, []
    while at + 9 <= len(data):
        op, length = data[at], struct.unpack("<Q", data[at + 1:at + 9])[0]
        if op == 0x06:
            found.append((at, length))
        at += 9 + length
    check(found, "a chunk in the file")
    return found


def minimal_mcap():
    """A valid MCAP file that someone else wrote: a Header, one channel
    without messages, a Footer."""
    def record(op, body):
        return bytes([op]) + struct.pack("<Q", len(body)) + body

    def string(s):
        return struct.pack("<I", len(s)) + s.encode()
    magic = b"\x89MCAP0\r\n"
    header = record(0x01, string("") + string("someone else"))
    channel = record(0x04, struct.pack("<HH", 1, 0) + string("/camera") + string("json") + struct.pack("<I", 0))
    data_end = record(0x0F, struct.pack("<I", 0))
    footer = record(0x02, struct.pack("<QQI", 0, 0, 0))
    return magic + header + channel + data_end + footer + magic


if __name__ == "__main__":
    try:
        main(globals())
    finally:
        for name in os.listdir(TMP):
            os.unlink(os.path.join(TMP, name))
        os.rmdir(TMP)
