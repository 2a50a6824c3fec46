"""Controllers in parallel on every core tcs may use (docs/DESIGN.md §2): one
controller on each core at a time, and results that do not depend on how
many cores there are."""

import os
import tempfile

from harness import (PYTHON, TCS_RUN, calibrate, charged_as_the_kernel_says, check, main, periodic_on_time,
                     periodic_reports, program_reports, prog, run, scenario_file, skip, tcs, trace_rows)


CORES = sorted(os.sched_getaffinity(0))
ONE = str(CORES[-1])

# Four 1 kHz loops, each computing 200 us a cycle, and a pendulum whose
# torque one of them never writes: the world steps with them.
WORLD = """\
[sim]
step = "1ms"

[[model]]
name = "pendulum"
type = "pendulum"
""" + "".join('[[controller]]\ncommand = "%s 1000 0.3 %dus"\n' % (prog("periodic"), 100 + 50 * i) for i in range(4))


def loops(r):
    """Each controller's key=value lines, in controller order (each prints
    its lines in one write at its end, so runs may interleave them)."""
    return sorted(periodic_reports(r.stdout), key=lambda v: int(v["loop_cpu_ns"]))


def trace_content(path):
    """What the trace says in virtual time: every wait (controller, kind,
    asked at, deadline, ended at) and every slice (its virtual span, the
    world's time and why it ended); not wall times or real CPU. Sorted:
    records of controllers running at once come in either order."""
    topics = {"/tcs/wait": ("controller", "kind", "v_request_ns", "deadline_ns", "v_end_ns", "absolute"),
              "/tcs/slice": ("controller", "v_start_ns", "v_end_ns", "sim_ns", "end")}
    content = {}
    for topic, fields in topics.items():
        rows = trace_rows(path, topic)
        check(rows and all(f in rows[0] for f in fields), "%s has %s" % (topic, ", ".join(fields)))
        content[topic] = sorted(tuple(row[f] for f in fields) for row in rows)
    return content


# Eight light loops (0 to 14 us a cycle): in lockstep, beside a polling
# coordinator, they are queued together on the other cores (lanes.cc).
LIGHT = """\
[sim]
step = "1ms"

[[model]]
name = "pendulum"
type = "pendulum"
""" + "".join('[[controller]]\ncommand = "%s 1000 0.3 %dus"\n' % (prog("periodic"), 2 * i) for i in range(8))


def lockstep_run(taskset, text=WORLD):
    d = tempfile.mkdtemp(prefix="tcs-test-cores-")
    path = os.path.join(d, "run.mcap")
    with scenario_file(text) as world:
        argv = [TCS_RUN, "-m", "lockstep", "--epoch", "2024-01-01T00:00:00Z", "--trace", path, "-w", world]
        r = run((["taskset", "-c", ONE] if taskset else []) + argv, timeout=120)
    check(r.returncode == 0, "the run succeeds", r)
    return r, path


def test_a_run_on_every_core_gives_what_one_core_gives():
    if len(CORES) < 2:
        skip("one core allowed here: nothing runs in parallel (the comparison is trivial)")
    wide, wide_trace = lockstep_run(taskset=False)
    narrow, narrow_trace = lockstep_run(taskset=True)
    a, b = loops(wide), loops(narrow)
    check(len(a) == len(b) == 4, "four controllers' results each", wide)
    for x, y in zip(a, b):
        for key in ("loops", "elapsed_s", "rate_hz", "misses", "sleep_failures"):
            check(x[key] == y[key], "%s the same on %d cores as on one: %s, %s" % (key, len(CORES), x[key], y[key]))
    print("  4 controllers: %s loops each, on %d cores and on one" % (a[0]["loops"], len(CORES)))
    ta, tb = trace_content(wide_trace), trace_content(narrow_trace)
    for topic in ta:
        check(ta[topic] == tb[topic], "the trace's %s records, in virtual time, the same (%d, %d)" %
              (topic, len(ta[topic]), len(tb[topic])))
    # Held to one core, everything ran there; free, the controllers used
    # every core (the coordinator's first: one alone stays with it).
    check(all(int(v["cores_seen"]) == 1 << int(ONE) for v in b), "taskset: every controller on CPU %s" % ONE)
    seen = 0
    for v in a:
        seen |= int(v["cores_seen"])
    check(seen == sum(1 << c for c in CORES), "controllers ran on every allowed core: seen %#x" % seen, wide)
    check(("on CPUs " if len(CORES) > 1 else "on CPU ") in wide.stderr, "the summary names the cores", wide)


def test_light_controllers_queued_on_a_core_give_what_one_core_gives():
    wide, wide_trace = lockstep_run(taskset=False, text=LIGHT)
    narrow, narrow_trace = lockstep_run(taskset=True, text=LIGHT)
    a, b = loops(wide), loops(narrow)
    check(len(a) == len(b) == 8, "eight controllers' results each", wide)
    for x, y in zip(a, b):
        check(x["loops"] == "300" and x["misses"] == "0", "300 loops, no misses: %s, %s" % (x["loops"], x["misses"]),
              wide)
        for key in ("loops", "elapsed_s", "rate_hz", "misses", "sleep_failures"):
            check(x[key] == y[key], "%s the same on %d cores as on one: %s, %s" % (key, len(CORES), x[key], y[key]))
    ta, tb = trace_content(wide_trace), trace_content(narrow_trace)
    for topic in ta:
        check(ta[topic] == tb[topic], "the trace's %s records, in virtual time, the same (%d, %d)" %
              (topic, len(ta[topic]), len(tb[topic])))
    print("  8 light controllers: 300 loops each, the same on %d cores and on one" % len(CORES))


def test_controllers_asleep_among_queued_ones_step_aside():
    # Two readers asleep in open(2) of a FIFO each, where no hook sees them,
    # among light loops queued on the same core: each is looked at, steps
    # aside while the others go on, and learns of the writer's line
    # (written at 0.2 s) at most a step late.
    d = tempfile.mkdtemp(prefix="tcs-test-cores-")
    text = LIGHT
    writer = os.path.join(d, "writer.sh")
    with open(writer, "w") as w:
        w.write("sleep 0.2\n")
        for i in range(2):
            fifo = os.path.join(d, "fifo%d" % i)
            os.mkfifo(fifo)
            w.write("echo hi%d > %s\n" % (i, fifo))
            reader = os.path.join(d, "reader%d.py" % i)
            with open(reader, "w") as f:
                f.write("import time\nt = time.monotonic()\nline = open(%r).read().strip()\n"
                        "print('got%d=%%s after%d=%%.6f' %% (line, time.monotonic() - t), flush=True)\n" %
                        (fifo, i, i))
            text += '[[controller]]\ncommand = "%s %s"\n' % (PYTHON, reader)
    text += '[[controller]]\ncommand = "sh %s"\n' % writer
    with scenario_file(text) as world:
        r = tcs("-m", "lockstep", "-w", world, timeout=120)
    check(r.returncode == 0, "the run succeeds", r)
    v = r.values()
    for i in range(2):
        check(v.get("got%d" % i) == "hi%d" % i, "reader %d got the writer's line" % i, r)
        after = float(v.get("after%d" % i, "-1"))
        # Two calls asleep outside the hooks, open(2) until the writer opens
        # and read(2) until it writes, each learnt of at most a step (1 ms)
        # late; never early.
        check(0.2 <= after <= 0.2 + 2 * 0.001, "reader %d: at 0.2 s of its time, two steps late at most: %.6f" %
              (i, after), r)
    check(len(loops(r)) == 8 and all(x["loops"] == "300" and x["misses"] == "0" for x in loops(r)),
          "the loops beside them kept their 1 kHz", r)
    print("  two readers, asleep in open(2) among 8 loops, got their lines after %s and %s s" %
          (v["after0"], v["after1"]))


def test_a_reader_woken_within_a_step_sees_no_time_before_the_write():
    # A writer runs ahead of the world within a step (it writes at 200.55 ms
    # of the step begun at 200 ms, then computes on): the reader it wakes,
    # asleep in open(2) and read(2) outside the hooks, reads a time no
    # earlier than the write, and at most a step later.
    d = tempfile.mkdtemp(prefix="tcs-test-cores-")
    fifo = os.path.join(d, "fifo")
    os.mkfifo(fifo)
    reader = os.path.join(d, "reader.py")
    with open(reader, "w") as f:
        f.write("import time\nline = open(%r).read().strip()\n"
                "print('got=%%s read_at=%%.9f' %% (line, time.monotonic()), flush=True)\n" % fifo)
    writer = os.path.join(d, "writer.py")
    with open(writer, "w") as f:
        f.write("import time\ntime.sleep(0.2005)\nf = open(%r, 'w')\nt = time.monotonic()\n"
                "f.write('hi\\n')\nf.close()\nprint('wrote_at=%%.9f' %% t, flush=True)\n"
                "sum(i * i for i in range(2000000))  # computing on, the world held at 200 ms\n" % fifo)
    text = LIGHT.split("[[controller]]")[0] + '[[controller]]\ncommand = "%s %s"\n[[controller]]\ncommand = "%s %s"\n' % (PYTHON, reader, PYTHON, writer)
    with scenario_file(text) as world:
        for mode in ("lockstep", "cpu"):
            r = tcs("-m", mode, "--epoch", "0", "-w", world, timeout=120)
            check(r.returncode == 0, "the run succeeds", r)
            v = r.values()
            check(v.get("got") == "hi", "the reader got the line", r)
            late = float(v["read_at"]) - float(v["wrote_at"])
            check(0 <= late <= 0.002, "%s: read %.6f s after the write: never before, two steps late at most" %
                  (mode, late), r)
            print("  %s: read %.1f us after the write" % (mode, late * 1e6))
    os.unlink(fifo)
    os.unlink(reader)
    os.unlink(writer)
    os.rmdir(d)


def test_a_controller_on_a_core_of_its_own_hands_off_through_shared_memory():
    # With a core of its own beside the coordinator's, a controller's
    # requests and their answers go through its clock page's mailbox
    # (tcs/mailbox.h): a 1 kHz loop's 3000 waits leave its core a handful
    # of times, where through the channel each leaves it at least once.
    # What it computes and sees is the same either way (with an epoch, a
    # spin's clock read costs the same in both runs: a fixed 25 ns).
    argv = ["-q", "--epoch", "0", prog("periodic"), "1000", "3", "0"]
    probe = tcs("-m", "lockstep", *argv[1:], timeout=60)
    if len(CORES) < 2 or "SCHED_FIFO on CPUs" not in probe.stderr:
        skip("%d core(s), %s: no mailbox here, every hand-off goes through the channel" %
             (len(CORES), "SCHED_FIFO" if "SCHED_FIFO" in probe.stderr else "no SCHED_FIFO"))
    for mode in ("lockstep", "cpu"):
        shared = tcs("-m", mode, *argv, timeout=60).values()
        channel = tcs("-m", mode, *argv, env={"TCS_NO_MAILBOX": "1"}, timeout=60).values()
        print("  %-8s 3000 waits: %s context switches through the mailbox, %s through the channel" %
              (mode, shared["switches"], channel["switches"]))
        if mode == "lockstep":
            check(shared["loops"] == channel["loops"] == "3000", "lockstep: 3000 loops either way")
            for key in ("elapsed_s", "rate_hz", "misses", "sleep_failures"):
                check(shared[key] == channel[key], "lockstep: %s the same: %s, %s" % (key, shared[key], channel[key]))
        else:
            for how, v in (("the mailbox", shared), ("the channel", channel)):
                periodic_on_time(v, 1000, 3, "cpu: through %s" % how)
        check(int(channel["switches"]) >= 3000, "%s: through the channel every wait leaves the core" % mode)
        # A wait leaves the core only when its answer takes longer than the
        # spin (TCS_MBOX_SPIN_NS, 30 us: above a ping-pong on the machines
        # seen, 3.5-20 us), so most do not.
        check(int(shared["switches"]) < 3000 / 2, "%s: through the mailbox fewer than half the waits do: %s" %
              (mode, shared["switches"]))


def test_cpu_mode_charges_each_controller_its_own_cpu_in_parallel():
    # In cpu mode each controller's time is its own CPU, whichever core it
    # ran on: a loop of 100 + 50 i us a cycle keeps its 1 kHz rate.
    with tempfile.TemporaryDirectory(prefix="tcs-test-cores-") as d, scenario_file(WORLD) as world:
        trace = os.path.join(d, "run.mcap")
        r = tcs("-m", "cpu", "--trace", trace, "-w", world, timeout=120)
        check(r.returncode == 0, "the run succeeds", r)
        slices, waits = trace_rows(trace, "/tcs/slice"), trace_rows(trace, "/tcs/wait")
    for i, v in enumerate(loops(r)):
        per_loop = int(v["loop_cpu_ns"]) / int(v["loops"])
        periodic_on_time(v, 1000, 0.3, "controller %d: 300 loops at 1 kHz" % i, r)
        check((100 + 50 * i) * 1000 <= per_loop, "controller %d computed its %d us a cycle: %.1f us" %
              (i, 100 + 50 * i, per_loop / 1e3), r)
    # A slice begun by a wake runs the wait's hook to its return first,
    # which is tcs's, not the program's: preempted, it was charged less than
    # the CPU it ran. (Preempted before the hook's mark, all of it was
    # charged, and a loop read its clock late by the hook's cost: about
    # 30 such slices in 5 runs.)
    woken = {(w["controller"], w["v_end_ns"]) for w in waits}
    after_wake = [s for s in slices if s["end"] == "preempted" and (s["controller"], s["v_start_ns"]) in woken]
    charged_all = [s for s in after_wake if int(s["charged_ns"]) >= int(s["cpu_ns"])]
    print("  %d preempted slices begun by a wake, %d charged their hook too" % (len(after_wake), len(charged_all)))
    check(not charged_all, "no preempted slice begun by a wake is charged its hook: %s" % charged_all[:3])


def test_controllers_preempted_at_every_step_are_charged_all_their_cpu():
    # Two computations of about 150 ms of CPU each, at two scales, beside a
    # world stepping every millisecond: each is preempted at every step its
    # time reaches first, on whichever core, and its virtual time is still
    # the CPU the kernel charged it times its scale. (Seen wrong on the
    # slow-clock setup, 56 ms each: a clock read whose CPU reading a
    # preemption interrupted ran 300 us ahead, 6 runs in 60; a
    # preemption's reading that lacked the end of the stop, lost, 3 in 60.)
    rounds = calibrate() * 150
    text = '[sim]\nstep = "1ms"\n\n[[model]]\nname = "pendulum"\ntype = "pendulum"\n' + "".join(
        '[[controller]]\ncommand = "%s %d x%g"\ncpu_scale = %g\n' % (prog("burn"), rounds, scale, scale)
        for scale in (3.0, 2.0))
    with tempfile.TemporaryDirectory(prefix="tcs-test-cores-") as d, scenario_file(text) as world:
        trace = os.path.join(d, "run.mcap")
        r = tcs("-m", "cpu", "--trace", trace, "-w", world, timeout=120)
        check(r.returncode == 0, "the run succeeds", r)
        preempted = [row["controller"] for row in trace_rows(trace, "/tcs/slice") if row["end"] == "preempted"]
    burns = {v["name"]: v for v in program_reports(r.stdout, "name")}
    check(sorted(burns) == ["x2", "x3"], "both computations report", r)
    for scale in (3.0, 2.0):
        charged_as_the_kernel_says(burns["x%g" % scale], scale, r)
    counts = [preempted.count(c) for c in ("1", "2")]
    check(min(counts) >= 100, "each was preempted at the world's steps: %s times" % counts)


if __name__ == "__main__":
    main(globals())
