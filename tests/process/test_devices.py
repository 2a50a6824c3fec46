"""Virtual devices (DESIGN.md §4) as a driver sees them: stream rate,
'latest', non-blocking reads, poll readiness, binary records, malformed
and saturated commands, a shadowed existing path with termios, and
scenario errors reported as FILE:LINE before anything starts."""

from harness import check, close_to, main, prog, scenario_file, tcs

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


def probe(world, *args, mode="lockstep"):
    r = tcs("-q", "-m", mode, "-w", world, prog("device_probe"), *args, timeout=30)
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
            else:  # records are due every ms of virtual time; reading costs a little
                for a, b in zip(times, times[1:]):
                    check(900000 <= b - a <= 1100000, "records a ms apart", r)
        r = probe(world, "stream", "/dev/null", "3")
        check(r.stdout.split() == ["record0_at=0", "record1_at=2000000", "record2_at=4000000"],
              "a shadowed existing path streams at its own rate (500 Hz)", r)


def test_nonblocking_reads_and_poll_readiness():
    with scenario_file(SCENARIO) as world:
        r = probe(world, "nonblock", "/dev/tcs/pendulum/state")
        check("first=1 second=-1 second_errno=EAGAIN third=1" in r.stdout,
              "O_NONBLOCK: a due record, then EAGAIN, then the next one a ms later", r)
        r = probe(world, "poll", "/dev/tcs/pendulum/state")
        check("poll=1 revents_in=1 waited=1000000" in r.stdout, "poll wakes when the next record is due", r)
        check("select=1 isset=1 waited=1000000" in r.stdout, "so does select", r)
        check("epoll_wait=1 fd_ok=1 waited=1000000" in r.stdout, "and epoll_wait", r)


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
    with scenario_file(SCENARIO) as world:
        r = probe(world, "write", "/dev/tcs/pendulum/torque", "/dev/tcs/pendulum/latest")
        v = r.values()
        check(v["ok"] == "4" and v["bad1"] == "-1" and v["bad1_errno"] == "EINVAL", "garbage: EINVAL", r)
        check(v["bad2"] == "-1" and v["bad2_errno"] == "EINVAL", "a wrong count of numbers: EINVAL", r)
        check("malformed record" in r.stderr, "and it is reported", r)
        check(v["read_open_of_actuator_errno"] == "EACCES", "an actuator is write-only", r)
        check(v["read_of_actuator"] == "-1" and v["read_of_actuator_errno"] == "EBADF", "so reading one fails", r)
        check(v["write_of_sensor"] == "-1" and v["write_of_sensor_errno"] == "EBADF", "a sensor is read-only", r)
        # Started at 1 rad, gravity decelerates it; 2 N*m (the last valid
        # command) adds 2 / (m L^2 / 3) = 6 rad/s^2: over 10 ms, velocity
        # 0.06 - 4.905 * sin(1) * 3 * 0.01 = -0.0638 rad/s.
        close_to(float(v["velocity_after_10ms"]), 0.06 - 14.715 * 0.8415 * 0.01, 0.05,
                 "the last valid command stays in force", r)
        # 100 N*m saturates at the 5 N*m limit: 15 rad/s^2 more for 10 ms.
        close_to(float(v["velocity_gain_next_10ms"]), (15 - 14.715 * 0.84) * 0.01, 0.1, "saturation at limit", r)


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
