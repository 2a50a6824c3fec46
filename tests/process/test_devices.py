"""Virtual devices (docs/DESIGN.md §4) as a driver sees them: stream rate,
'latest', non-blocking reads, poll readiness, binary records, malformed
and saturated commands, a shadowed existing path with termios, and
scenario errors reported as FILE:LINE before anything starts."""

import math
import os
import re
import tempfile

from harness import AHEAD, READ, check, main, prog, scenario_file, tcs, trace_rows



SCENARIO = """\
[sim]
step = "1ms"
model = "pendulum"

[model]
initial_angle = 1.0

[[device]]
path = "/dev/tcs/pendulum/state"
kind = "sensor"
signals = ["pendulum.hinge.position", "pendulum.hinge.velocity"]
format = "text"
mode = "stream"
rate = "1kHz"

[[device]]
path = "/dev/tcs/pendulum/latest"
kind = "sensor"
signals = ["pendulum.hinge.position", "pendulum.hinge.velocity"]
mode = "latest"

[[device]]
path = "/dev/tcs/pendulum/binary"
kind = "sensor"
signals = ["pendulum.hinge.position", "pendulum.hinge.velocity"]
format = "binary"
mode = "latest"

[[device]]
path = "/dev/null"
kind = "sensor"
signals = ["pendulum.hinge.position"]
rate = "500Hz"

[[device]]
path = "/dev/tcs/pendulum/torque"
kind = "actuator"
signals = ["pendulum.hinge.effort"]
limit = 5.0
"""

# Two motors, one written in text, one in binary.
TWO_MOTORS = """\
[sim]
step = "1ms"

[[model]]
name = "a"
type = "pendulum"

[[model]]
name = "b"
type = "pendulum"

[[device]]
path = "/dev/tcs/a/torque"
kind = "actuator"
signals = ["a.hinge.effort"]
limit = 5.0

[[device]]
path = "/dev/tcs/b/torque_f64"
kind = "actuator"
signals = ["b.hinge.effort"]
format = "binary"
"""


def probe(world, *args, mode="lockstep"):
    r = tcs("-q", "-m", mode, "--no-slack", "--spin-cost", "0", "-w", world, prog("device_probe"), *args, timeout=30)
    check(r.returncode == 0, "device_probe %s succeeds" % " ".join(args), r)
    return r


def test_stream_records_come_at_the_rate():
    with scenario_file(SCENARIO) as world:
        for mode in ("lockstep", "cpu"):
            r = probe(world, "stream", "/dev/tcs/pendulum/state", "5", mode=mode)
            times = [int(r.values()["record%d_at" % i]) for i in range(5)]
            print("  %s: records read at %s ns" % (mode, times))
            if mode == "lockstep":
                check(times == [0, 1000000, 2000000, 3000000, 4000000], "one record per ms, when due", r)
            else:
                # Record k is due at k ms of virtual time, D + k ms on the
                # program's clock (D unknown: its start-up's CPU). A read
                # returns at its record's time, or at once if the program is
                # later than that; either way later by what it computes in
                # the read, as the kernel's CPU clock says (a first read's
                # page faults, a pause of the VM: charged as CPU too; the
                # kernel's account, which tcs's charges may not exceed). Each time
                # read is an estimate within AHEAD of the truth, either way
                # (harness.charged_as_the_kernel_says). No read is early, so
                # D is at most the least of at_k - k ms (+ AHEAD); with that
                # D no read may be late. A read begins at the time read after
                # the one before, plus the CPU from there (cpu0_k - cpu_k-1,
                # and the CPU-clock read that follows the time's: READ).
                v = r.values()
                cpu0 = [int(v["record%d_cpu0" % k]) for k in range(5)]
                cpu = [int(v["record%d_cpu" % k]) for k in range(5)]
                d = min(t - k * 1000000 for k, t in enumerate(times)) + AHEAD
                for k in range(1, 5):
                    due = d + k * 1000000
                    began = times[k - 1] + AHEAD + READ + cpu0[k] - cpu[k - 1]
                    latest = max(due, began) + cpu[k] - cpu0[k] + AHEAD
                    check(times[k] <= latest, "record %d read at %d ns, due by %d ns, expected by %d ns"
                          % (k, times[k], due, latest), r)
        r = probe(world, "stream", "/dev/null", "3")
        at = [t for t in r.stdout.split() if "_at=" in t]
        check(at == ["record0_at=0", "record1_at=2000000", "record2_at=4000000"],
              "a shadowed existing path streams at its own rate (500 Hz)", r)


def test_nonblocking_reads_and_poll_readiness():
    with scenario_file(SCENARIO) as world:
        r = probe(world, "nonblock", "/dev/tcs/pendulum/state")
        v = r.values()
        check((v["first"], v["more"], v["drain_errno"], v["drain_ns"], v["third"]) == ("1", "0", "EAGAIN", "0", "1"),
              "O_NONBLOCK: a due record, then EAGAIN at once, then the next one a ms later", r)
        r = probe(world, "poll", "/dev/tcs/pendulum/state")
        check("poll=1 revents_in=1 waited=1000000" in r.stdout, "poll wakes when the next record is due", r)
        check("select=1 isset=1 waited=1000000" in r.stdout, "so does select", r)
        check("epoll_wait=1 fd_ok=1 waited=1000000" in r.stdout, "and epoll_wait", r)
        # In cpu mode the program's time moves with its CPU between reads.
        # Rules: a non-blocking read never waits, so a drain to EAGAIN
        # takes the virtual time of its CPU and no more; a wait for
        # readiness ends when the next record is due, at most a record's
        # period (1 ms) after it began, plus its own CPU. device_probe
        # reads the CPU before and after each window's two time reads,
        # each within AHEAD of the truth either way.
        r = probe(world, "nonblock", "/dev/tcs/pendulum/state", mode="cpu")
        v = r.values()
        # (Opened after 0, the program finds its first record due at the
        # next whole ms: its first read may be EAGAIN already.)
        check(v["drain_errno"] == "EAGAIN" and v["third"] == "1",
              "cpu mode: reads end in EAGAIN, and a ms later a record is there", r)
        check(int(v["drain_ns"]) <= int(v["drain_cpu_ns"]) + 2 * AHEAD,
              "cpu mode: the drain (%s reads) waited for nothing" % v["more"], r)
        r = probe(world, "poll", "/dev/tcs/pendulum/state", mode="cpu")
        v = r.values()
        for call, ready in (("poll", "revents_in"), ("select", "isset"), ("epoll_wait", "fd_ok")):
            check(v[call] == "1" and v[ready] == "1", "cpu mode: %s reports the stream readable" % call, r)
        waits = re.findall(r"(\w+)=1 \w+=1 waited=(\d+) \w+_cpu=(\d+)", r.stdout)
        check(len(waits) == 3, "three waits reported", r)
        for call, waited, cpu in waits:
            check(0 < int(waited) <= 1000000 + int(cpu) + 2 * AHEAD,
                  "cpu mode: %s waited %s ns, for the next record (its CPU %s ns)" % (call, waited, cpu), r)


def test_a_stalled_reader_keeps_the_newest_records():
    """A stream keeps at most 4096 unread records, the oldest dropped
    (docs/DESIGN.md §4): of a 1 kHz stream, a reader that reads nothing for 6 s
    then finds the one record its descriptor held when it stopped and the
    newest 4096, in order, all as another reader of the stream saw them;
    then it reads on, the next record when it is due. The drop is reported."""
    with scenario_file(SCENARIO) as world:
        r = probe(world, "overflow", "/dev/tcs/pendulum/state", "6000")
        v = r.values()
        print("  drained %s records: %s of the 6000 the other reader saw" % (v["records"], v["runs"]))
        check(v["missing"] == "0" and v["drained_errno"] == "EAGAIN", "every record drained is one of the stream's", r)
        check(v["runs"] == "0-0,1904-5999" and v["records"] == "4097",
              "the record held, then the newest 4096 (%s)" % v["runs"], r)
        check(v["next_same"] == "1" and v["next_at"] == "6000000000", "the next record, read when due", r)
        check(r.stderr.count("more than 4096 records unread: the oldest are dropped") == 1,
              "the drop is reported once", r)


def test_latest_and_binary_records():
    with scenario_file(SCENARIO) as world:
        r = probe(world, "latest", "/dev/tcs/pendulum/latest")
        check("reads=1 same_instant_equal=1 later_differs=1" in r.stdout,
              "latest: every read answers, with the world at that instant", r)
        r = probe(world, "binary", "/dev/tcs/pendulum/binary")
        v = r.values()
        check(v["bytes"] == "16" and v["position"] == "1.000000" and v["velocity"] == "0.000000",
              "binary: two little-endian f64 per record (the initial state)", r)


def test_commands_hold_and_malformed_ones_fail():
    # Both modes: in lockstep a well-formed write needs no round trip, a
    # malformed one must fail all the same.
    with scenario_file(SCENARIO) as world:
        for mode in ("lockstep", "cpu"):
            r = probe(world, "write", "/dev/tcs/pendulum/torque", "/dev/tcs/pendulum/latest", mode=mode)
            v = r.values()
            check(v["several"] == "1" and v["ok"] == "4" and v["bad1"] == "-1" and v["bad1_errno"] == "EINVAL", "garbage: EINVAL", r)
            check(v["bad2"] == "-1" and v["bad2_errno"] == "EINVAL", "a wrong count of numbers: EINVAL", r)
            check("malformed record" in r.stderr, "and it is reported", r)
            check(v["read_open_of_actuator_errno"] == "EACCES", "an actuator is write-only", r)
            check(v["rdwr_open_of_actuator_errno"] == "EACCES" and v["rdwr_open_of_sensor_errno"] == "EACCES",
                  "neither opens for reading and writing", r)
            check(v["read_of_actuator"] == "-1" and v["read_of_actuator_errno"] == "EBADF", "so reading one fails", r)
            check(v["write_of_sensor"] == "-1" and v["write_of_sensor_errno"] == "EBADF", "a sensor is read-only", r)
            if mode == "cpu":
                continue  # its CPU moves when each command starts: the figures below are lockstep's
            # The pendulum's own equation (simhost/ode_pendulum.cc: a 1 kg,
            # 1 m rod on a hinge, I = m L^2 / 3, gravity 9.81 at L / 2),
            # stepped as ODE's dWorldStep steps it: 1 ms steps, velocity
            # first, then the angle with the new velocity. From rest at
            # 1 rad: 10 steps under 2 N*m (the last of three written at one
            # instant, the last valid one), then 10 under 100 N*m held to
            # the 5 N*m limit. Beyond that equation ODE has the hinge's
            # softness (CFM 1e-10 over a 1 ms step: its force, under 10 N,
            # off by under 1e-7 of itself, an impulse under 1e-9 N*s a
            # step, which at 0.5 m from the rod's centre (I = m L^2 / 12)
            # turns it by under 1e-8 rad/s) and its ERP's pull back onto
            # the rod's circle (radial, second order in the angle a step
            # turns): 1e-7 rad/s over 10 steps. (The hand linearisation
            # this replaces was 1.3e-5 off; a command a step late, 6e-3.)
            def steps(angle, velocity, torque, n):
                for _ in range(n):
                    velocity += 1e-3 * (torque - 9.81 * 0.5 * math.sin(angle)) / (1.0 / 3)
                    angle += 1e-3 * velocity
                return angle, velocity
            angle, after_10ms = steps(1.0, 0.0, 2.0, 10)
            gain = steps(angle, after_10ms, 5.0, 10)[1] - after_10ms
            got = float(v["velocity_after_10ms"])
            check(abs(got - after_10ms) <= 1e-7,
                  "of several commands at one instant the last, the last valid, stays in force: %.9f rad/s, "
                  "the model's %.9f" % (got, after_10ms), r)
            got = float(v["velocity_gain_next_10ms"])
            check(abs(got - gain) <= 1e-7,
                  "100 N*m saturates at the 5 N*m limit: %.9f rad/s more, the model's %.9f" % (got, gain), r)


def test_commands_keep_the_time_they_were_written():
    """In lockstep a write of whole, well-formed records goes on without a
    round trip and the coordinator takes it at the next request: the trace
    must still show every command at the virtual time it was written, in
    order, none lost (a flood with no wait, the last one before exit), and
    a malformed one must still fail its write."""
    with scenario_file(TWO_MOTORS) as world, tempfile.TemporaryDirectory() as tmp:
        trace = os.path.join(tmp, "run.mcap")
        r = tcs("-q", "-m", "lockstep", "--no-slack", "-w", world, "-t", trace, prog("device_probe"), "batches",
                "/dev/tcs/a/torque", "/dev/tcs/b/torque_f64", timeout=60)
        check(r.returncode == 0, "device_probe batches succeeds", r)
        v = r.values()
        check((v["whole"], v["piece1"], v["piece2"], v["hex"]) == ("4", "2", "2", "6"),
              "whole records, pieces and a hex float are written", r)
        check(v["overflow"] == "-1" and v["overflow_errno"] == "EINVAL", "1e999 is no number: EINVAL", r)
        check((v["two"], v["bin_two"], v["bin_piece1"], v["bin_piece2"]) == ("6", "16", "7", "1"),
              "two records at once, binary whole and in pieces", r)
        check(v["flooded"] == "30000", "30,000 writes without a wait all go through (no hang)", r)
        rows = [(int(x["v_ns"]), x["path"].rsplit("/", 1)[1], x["values[0]"], x["malformed"])
                for x in trace_rows(trace, "/tcs/device")]
        ms = 1000000
        ok = lambda at, dev, value: (at, dev, value, "false")
        expected = ([ok(0, "torque", "1.5"), ok(0, "torque", "2.5"), ok(0, "torque", "2"),
                     (0, "torque", "", "true"),
                     ok(3 * ms, "torque", "3"), ok(3 * ms, "torque", "4"),
                     ok(3 * ms, "torque_f64", "-1.25"), ok(3 * ms, "torque_f64", "0.5"),
                     ok(3 * ms, "torque_f64", "6")] +
                    [ok(5 * ms, "torque", "0.25")] * 30000 + [ok(5 * ms, "torque", "4.5")])
        print("  %d commands traced; first %s, last %s" % (len(rows), rows[:4], rows[-1:]))
        check(len(rows) == len(expected), "every command traced (%d, expected %d)" % (len(rows), len(expected)))
        for i, (got, want) in enumerate(zip(rows, expected)):
            check(got == want, "command %d is %s, traced as %s" % (i, want, got))


def test_a_serial_port_path_takes_termios():
    with scenario_file(SCENARIO) as world:
        r = probe(world, "termios", "/dev/null")
        check("tcgetattr=0 tcsetattr=0 tcflush=0 speed_ok=1 record=1" in r.stdout,
              "termios calls succeed on a device, as on /dev/ttyUSB0", r)


def test_scenario_errors_name_file_and_line():
    cases = [
        (SCENARIO.replace('rate = "1kHz"', 'rate = "fast"'), 14, "rate"),
        (SCENARIO.replace('"pendulum.hinge.effort"]', '"pendulum.hinge.efort"]'), 38, "pendulum.hinge.efort"),
        (SCENARIO.replace('"pendulum.hinge.effort"]', '"pendulum.rod.pose"]'), 38, "pendulum.rod.pose"),
        (SCENARIO.replace("initial_angle = 1.0", "initial_angle = 1.0\nlenght = 2"), 7, "lenght"),
        (SCENARIO.replace('model = "pendulum"', 'model = "pendulun"'), 11, "pendulun"),
        ('[sim]\nmodel = "pendulun"\n', 2, "pendulun"),
        (SCENARIO.replace('kind = "actuator"', 'kind = "actuator"\nmode = "latest"'), 38, "mode"),
        (SCENARIO.replace('"pendulum.hinge.position"]\nrate', '"pendulum.hinge.angle"]\nrate'), 32, "angle"),
        (SCENARIO + "\n[[device\n", 41, ""),
    ]
    for text, line, word in cases:
        with scenario_file(text) as world:
            r = tcs("-w", world, "--", "true")
            check(r.returncode == 2, "a bad scenario exits 2", r)
            check(r.stderr.startswith("tcs-run: %s:%d: " % (world, line)), "FILE:LINE (%d) first" % line, r)
            check(word in r.stderr and r.stderr.count("\n") == 1, "one line naming '%s'" % word, r)


def test_list_signals():
    r = tcs("--list-signals")
    check(r.returncode == 0, "--list-signals succeeds", r)
    for name in ("pendulum.hinge.position", "pendulum.hinge.velocity", "pendulum.hinge.effort",
                 "/dev/tcs/pendulum/state", "/dev/tcs/pendulum/torque"):
        check(name in r.stdout, "lists " + name, r)


if __name__ == "__main__":
    main(globals())
