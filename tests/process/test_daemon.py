"""coordinatord and tcs-run --connect (docs/DESIGN.md §5): controllers attached
to one shared world keep their rates and get their exit statuses back, the
world waits for the controllers its scenario expects, a client's signals
reach its controller, another user is refused, bad requests are answered,
and SIGTERM ends the daemon cleanly with its trace readable."""

import json
import os
import re
import signal
import socket
import stat
import struct
import tempfile
import time

from daemon import (CLOCK_LISTEN, COORDINATORD, DDS_ENV, EXAMPLES, PERIODIC, Daemon, cycles_line,
                    mcap_counts, trace_summary)
from harness import (TCS_RUN, TCS_TRACE, calibrate, charged_as_the_kernel_says, check, finish, main, prog, run, start,
                     trace_rows)

STEP_NS = 10**6  # the scenarios' step below

TWO_CONTROLLERS = """
[sim]
step = "1ms"
model = "pendulum"

[[controller]]
command = "periodic 1000 2 20us"

[[controller]]
command = "periodic 250 3 40us"
"""


def test_two_controllers_share_one_world_and_keep_their_rates():
    with Daemon(TWO_CONTROLLERS) as d:
        fast = d.connect(prog("periodic"), 1000, 2, "20us")
        d.wait_log(r"attached .*periodic .*1 of 2 expected")
        # The world waits for the second: nothing may run meanwhile (a world
        # that ran would say so at once; that both begin at its time 0 is
        # checked below).
        time.sleep(0.3)
        check("the world runs" not in d.log(), "the world is held until both have attached", None)
        slow = d.connect(prog("periodic"), 250, 3, "40us")
        a = finish(fast, 60, fast.t0)
        b = finish(slow, 60, slow.t0)
        check("every expected controller has attached: the world runs" in d.log(), "the world starts", None)
        check(d.stop() == 0, "SIGTERM ends coordinatord with status 0", None)
    for r, cycles, rate in ((a, 2000, 1000.0), (b, 750, 250.0)):
        check(r.returncode == 0, "tcs-run --connect ends with the controller's status", r)
        v = r.values()
        check(int(v["loops"]) == cycles, "%d cycles at %g Hz" % (cycles, rate), r)
        # Work of 2 % and 1 % of the period misses no deadline, unless a
        # pause of the machine, charged as CPU by the kernel too, made a
        # round longer than its period (periodic.c: pause_misses).
        check(int(v["misses"]) <= int(v["pause_misses"]), "the loop keeps its deadlines", r)
        check(re.search(r"tcs-run: .* virtual in .* wall", r.stderr), "tcs-run prints its summary", r)
    s = trace_summary(d.trace)
    ctl = sorted(s["controllers"], key=lambda c: c["controller"])
    check(len(ctl) == 2, "the trace has both controllers: %s" % ctl)
    check([c["cycles"] for c in ctl] == [2000, 750], "the trace counts each one's cycles: %s" % ctl)
    # Held until both had come, both began at virtual time 0.
    check(all(c["start_ns"] == 0 for c in ctl), "both start at the world's time 0: %s" % ctl)
    counts = mcap_counts(d.trace)
    check(not counts["truncated"] and counts["topics"]["/tcs/controller"] == 2, "the trace is complete: %s" % counts)


def test_cpu_scale_of_tcs_run_over_the_worlds():
    # Of two controllers the world expects with cpu_scale 2, the one
    # attached with --cpu-scale 3 runs at 3, the other at 2.
    rounds = calibrate() * 50  # about 50 ms of CPU
    world = '[sim]\nmodel = "pendulum"\n' + '[[controller]]\ncommand = "burn"\ncpu_scale = 2.0\n' * 2
    with Daemon(world) as d:
        given = d.connect(prog("burn"), rounds, opts=["--cpu-scale", "3"])
        d.wait_log(r"attached .*burn .*1 of 2 expected")
        entry = d.connect(prog("burn"), rounds)
        results = [(finish(p, 60, p.t0), scale) for p, scale in ((given, 3.0), (entry, 2.0))]
    for r, scale in results:
        check(r.returncode == 0, "burn runs attached", r)
        charged_as_the_kernel_says(r.values(), scale, r)


def test_the_pendulum_experiment_comes_out_as_in_process():
    # The built-in world, written out, expecting the controller: held until
    # it attaches, the run is the in-process one, bit for bit in lockstep.
    src = os.environ.get("TCS_SCENARIOS", "scenarios")
    with open(os.path.join(src, "pendulum.toml")) as f:
        world = f.read() + '\n[[controller]]\ncommand = "pendulum_pd"\n'
    pd = os.path.join(EXAMPLES, "pendulum_pd")
    alone = run([TCS_RUN, "-q", "-m", "lockstep", "--", pd, "--seconds", "10"])
    with Daemon(world, "--mode", "lockstep") as d:
        p = d.connect(pd, "--seconds", 10, opts=["-q"])
        shared = finish(p, 60, p.t0)
    for r in (alone, shared):
        check(r.returncode == 0 and "balanced=1" in r.stdout, "the pendulum is balanced", r)
    check(alone.values() == shared.values(), "the same outcome, figure for figure:\n%s\n%s" % (alone.stdout, shared.stdout))


def test_a_controller_joins_a_running_world_at_its_time():
    # No [[controller]]: the world runs at once, at real-time speed while
    # nobody is attached.
    t0 = time.monotonic()
    with Daemon('[sim]\nmodel = "pendulum"\n', "--mode", "lockstep") as d:
        time.sleep(0.5)
        p = d.connect(PERIODIC, "--rate", 100, "--seconds", 1)
        d.wait_log(r"attached .*periodic_controller")
        attached = time.monotonic() - t0
        r = finish(p, 60, p.t0)
        check(r.returncode == 0 and cycles_line(r)[0] == 100, "its loop runs", r)
    ctl = trace_summary(d.trace)["controllers"]
    check(len(ctl) == 1, "one controller: %s" % ctl)
    start = ctl[0]["start_ns"]
    check(start <= attached * 1e9, "never ahead of real time: %d ns, attached %.3f s after the daemon's start" %
          (start, attached))
    # It began where the world was, not at 0: at the last step before it
    # (or within the step that follows), which the world reached at the
    # pace of real time, as the trace's wall clock says: never ahead of it
    # (each step's time no later than the wall time since the run began:
    # the pace is anchored where the world began to idle, which is not
    # before that; not measured from the first step, which may itself have
    # come late and been caught up), and behind by no more than
    # kIdleCatchUp (50 ms: an idle world that falls behind catches up at
    # once, up to that; world_steps.cc) and what pauses of the machine took. A pause shows as a step more than a
    # whole step late (a gap over 2 steps between two; a timer's lateness
    # is caught up at the next step), and loses at most its length beyond
    # the step, when its lateness, alone or with the next ones before the
    # world caught up, went over 50 ms (the world goes on from then).
    rows = trace_rows(d.trace, "/tcs/step")
    steps = [(int(row["v_ns"]), int(row["wall_ns"])) for row in rows if int(row["v_ns"]) <= start]
    check(len(steps) > 1, "the world stepped before it joined")
    (v0, w0), (vl, wl) = steps[0], steps[-1]
    check(vl <= start <= vl + STEP_NS, "it joins at the world's time: %d ns, the world at %d ns" % (start, vl), r)
    lost = sum(b[1] - a[1] - STEP_NS for a, b in zip(steps, steps[1:]) if b[1] - a[1] > 2 * STEP_NS)
    ahead = max(v - w for v, w in steps)
    check(ahead <= 0, "the idle world never ahead of real time: a step %d ns ahead of the run's wall clock" % ahead, r)
    check(wl - w0 - 50 * 10**6 - lost <= vl - v0,
          "the idle world at real-time pace: %d ns of virtual time in %d ns of wall time (%d ns lost to gaps)" %
          (vl - v0, wl - w0, lost), r)
    check(wl >= 0.5e9, "the world was 0.5 s old when it joined: the step before at %d ns of wall time" % wl, r)


def test_exit_statuses_environment_and_folder_come_back():
    with Daemon('[sim]\nmodel = "pendulum"\n') as d:
        runs = [
            d.connect(prog("exit_with"), 7),
            d.connect(prog("exit_with"), "abort"),
            d.connect("/bin/sh", "-c", 'pwd; echo "FOO=$FOO"; read line; echo "got $line"; exit 3',
                      env={"FOO": "bar"}),
        ]
        results = [finish(p, 60, p.t0) for p in runs]
    seven, aborted, shell = results
    check(seven.returncode == 7, "exit 7 comes back", seven)
    check(aborted.returncode == 128 + signal.SIGABRT, "death by SIGABRT comes back as 134", aborted)
    check("killed by SIGABRT" in aborted.stderr, "the summary says how it ended", aborted)
    check(shell.returncode == 3, "the shell's exit 3 comes back", shell)
    check("FOO=bar" in shell.stdout, "the caller's environment reaches the controller", shell)
    # The daemon works in its own folder; the controller in its caller's.
    check(shell.stdout.splitlines()[0] == os.getcwd(), "the caller's working directory", shell)
    check("got " in shell.stdout, "stdin is the caller's (here /dev/null: an empty read)", shell)


def catches(pid, signo, timeout=10):
    """Whether process pid has a handler for signo within timeout seconds
    (its /proc status's SigCgt)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        with open("/proc/%d/status" % pid) as f:
            caught = int(re.search(r"^SigCgt:\s*([0-9a-f]+)", f.read(), re.M).group(1), 16)
        if caught >> (signo - 1) & 1:
            return True
        time.sleep(0.02)
    return False


def test_ctrl_c_at_tcs_run_reaches_the_controller():
    with Daemon('[sim]\nmodel = "pendulum"\n') as d:
        p = d.connect(PERIODIC, "--rate", 1000, "--seconds", 1000)
        d.wait_log(r"attached .*periodic_controller")
        # Ctrl-C once it runs, its handler in place: attached is said as
        # the preload starts, before the program's main (0.5 s after it,
        # on a loaded machine, was once not enough).
        check(catches(d.controller_pids()[0], signal.SIGINT), "the controller sets its SIGINT handler")
        time.sleep(0.2)
        p.send_signal(signal.SIGINT)
        r = finish(p, 30, p.t0)
        # periodic_controller ends its loop on SIGINT and reports it.
        check(r.returncode == 0, "the controller's own status after its SIGINT handler", r)
        # It ran its loop until then: n cycles at 1 kHz, the last period cut
        # by Ctrl-C, are no faster than n / (n - 1) ms (0.05: the rate is
        # printed to 0.1 Hz); slower only by lateness.
        n, hz, _ = cycles_line(r)
        check(n > 1 and hz <= 1000.0 * n / (n - 1) + 0.05, "it ran until Ctrl-C", r)

        # One that ignores SIGINT: a second Ctrl-C kills it.
        q = d.connect("/bin/sh", "-c", "trap '' INT; while :; do sleep 0.01; done")
        d.wait_log(r"attached /bin/sh")
        time.sleep(0.3)
        q.send_signal(signal.SIGINT)
        # (A forwarded signal is delivered at once: 0.3 s is thirty of the
        # shell's rounds, in which one that killed it would have.)
        time.sleep(0.3)
        check(q.poll() is None, "SIGINT ignored: it runs on", None)
        q.send_signal(signal.SIGINT)
        r = finish(q, 30, q.t0)
        check(r.returncode == 128 + signal.SIGKILL, "the second Ctrl-C is SIGKILL", r)


def test_a_client_gone_takes_its_controller():
    with Daemon('[sim]\nmodel = "pendulum"\n') as d:
        p = d.connect(PERIODIC, "--rate", 1000, "--seconds", 1000)
        d.wait_log(r"attached .*periodic_controller")
        pid = d.controller_pids()[-1]
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        d.wait_log(r"\(controller 1\) ended", timeout=10)
        check(not os.path.exists("/proc/%d/cmdline" % pid) or not open("/proc/%d/cmdline" % pid).read(),
              "its controller has ended", None)
        # The daemon serves on.
        r = finish(d.connect(prog("exit_with"), 5), 60, time.monotonic())
        check(r.returncode == 5, "the next client is served", r)


def test_a_controller_gone_before_the_start_is_waited_for_again():
    with Daemon(TWO_CONTROLLERS) as d:
        p = d.connect(prog("periodic"), 1000, 1, 0)
        d.wait_log(r"1 of 2 expected")
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        d.wait_log(r"the world waits for periodic, periodic again")
        runs = [d.connect(prog("periodic"), 1000, 1, 0) for _ in range(2)]
        for q in runs:
            r = finish(q, 60, q.t0)
            check(r.returncode == 0 and r.values()["loops"] == "1000", "the two that came next run the world", r)
        check(d.log().count("2 of 2 expected") == 1, "the world started with both\n" + d.log())


def test_a_long_served_daemon_keeps_no_descriptors_of_ended_controllers():
    with Daemon('[sim]\nmodel = "pendulum"\n') as d:
        fds = lambda: len(os.listdir("/proc/%d/fd" % d.proc.pid))
        r = finish(d.connect(prog("exit_with"), 0), 60, time.monotonic())
        before = fds()
        for _ in range(60):
            r = finish(d.connect(prog("exit_with"), 0), 60, time.monotonic())
            check(r.returncode == 0, "each one is served", r)
        # The last client's end reaches the daemon just after it has exited
        # (its socket, its controller's pidfd): give it a moment. A leak
        # per controller would be 60 or more.
        deadline = time.monotonic() + 5
        while fds() > before + 2 and time.monotonic() < deadline:
            time.sleep(0.02)
        after = fds()
        check(after <= before + 2, "descriptors: %d after one controller, %d after 60 more" % (before, after))


def test_another_user_is_refused():
    if os.geteuid() != 0:
        raise AssertionError("this test switches to another uid and needs root")
    with Daemon('[sim]\nmodel = "pendulum"\n') as d:
        mode = stat.S_IMODE(os.stat(d.socket).st_mode)
        check(mode == 0o600, "the socket is 0600, not %o" % mode)
        # Past the file's permission (opened up by root), SO_PEERCRED refuses.
        os.chmod(d.socket, 0o666)
        os.chmod(d.dir, 0o711)
        pid = os.fork()
        if pid == 0:
            try:
                os.setgroups([])
                os.setresgid(65534, 65534, 65534)
                os.setresuid(65534, 65534, 65534)
                s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
                s.settimeout(10)
                s.connect(d.socket)
                kind, text = read_frames(s)[0]
                os._exit(0 if kind == 4 and b"serves uid 0 only, not uid 65534" in text else 1)
            except Exception:
                os._exit(2)
        _, status = os.waitpid(pid, 0)
        check(os.waitstatus_to_exitcode(status) == 0, "uid 65534 gets REFUSED naming both uids\n" + d.log())
        check("refused a client (uid 65534)" in d.log(), "the daemon logs the refusal\n" + d.log())
        os.chmod(d.socket, 0o600)
        # And the daemon still serves its own user.
        r = finish(d.connect(prog("exit_with"), 0), 60, time.monotonic())
        check(r.returncode == 0, "its own user is served", r)


def read_frames(s):
    """Every frame (kind, payload) the daemon sends on s until it closes."""
    data = b""
    while True:
        chunk = s.recv(4096)
        if not chunk:
            break
        data += chunk
    frames = []
    while len(data) >= 16:
        _, _, kind, length = struct.unpack("<IHHI", data[:12])
        frames.append((kind, data[16:16 + length]))
        data = data[16 + length:]
    return frames


def raw_request(path, data, fds=()):
    """Sends bytes (with fds) and returns (kind, text) of the reply."""
    s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    s.settimeout(10)
    s.connect(path)
    if fds:
        s.sendmsg([data], [(socket.SOL_SOCKET, socket.SCM_RIGHTS, struct.pack("%di" % len(fds), *fds))])
    else:
        s.sendall(data)
    kind, payload = read_frames(s)[0]
    s.close()
    return kind, payload.decode(errors="replace")


def frame(kind, payload, magic=0x41534354, version=1, length=None):
    return struct.pack("<IHHII", magic, version, kind, len(payload) if length is None else length, 0) + payload


def run_payload(path, cwd, argv, env=()):
    def s(b):
        return struct.pack("<I", len(b)) + b
    out = struct.pack("<d", 0.0) + s(path) + s(cwd) + struct.pack("<II", len(argv), len(env))
    return out + b"".join(s(a) for a in argv) + b"".join(s(e) for e in env)


def test_bad_requests_are_answered_and_the_daemon_serves_on():
    REFUSED = 4
    with Daemon('[sim]\nmodel = "pendulum"\n') as d:
        cases = [
            (b"GET / HTTP/1.0\r\n\r\n", (), "not a tcs attach request"),
            (frame(1, b"", version=9), (), "version 9"),
            (frame(1, b"", length=1 << 30), (), "the limit is"),
            (frame(1, b"\x00" * 3), (), "malformed run request"),
            (frame(1, run_payload(b"bin/true", b"/", [b"true"])), (), "not absolute"),
            (frame(1, run_payload(b"/bin/true", b"/", [b"true"], [b"NOEQUALS"])), (), "without '='"),
            (frame(1, run_payload(b"/bin/true", b"/", [b"true"])), (), "without stdin, stdout and stderr"),
            (frame(2, struct.pack("<i", 2)), (), "unexpected frame"),
        ]
        for data, fds, words in cases:
            kind, text = raw_request(d.socket, data, fds)
            check(kind == REFUSED and words in text, "refused with %r: got %d %r" % (words, kind, text))
        # A program that cannot be executed: exit 127 comes back, with why.
        devnull = os.open("/dev/null", os.O_RDWR)
        s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        s.connect(d.socket)
        s.sendmsg([frame(1, run_payload(b"/nonexistent/program", b"/", [b"program"]))],
                  [(socket.SOL_SOCKET, socket.SCM_RIGHTS, struct.pack("3i", devnull, devnull, devnull))])
        os.close(devnull)
        s.settimeout(20)
        kinds = read_frames(s)
        check([k for k, _ in kinds] == [3, 5], "STARTED then ENDED: %s" % kinds)
        check(struct.unpack("<i", kinds[1][1][:4])[0] >> 8 == 127, "exit 127 for a program that is not there")
        r = finish(d.connect(prog("exit_with"), 4), 60, time.monotonic())
        check(r.returncode == 4, "the daemon serves on after bad requests", r)


def test_command_line_errors():
    r = run([COORDINATORD])
    check(r.returncode == 2 and "--world FILE is required" in r.stderr, "--world is required", r)
    r = run([COORDINATORD, "--world", "/nonexistent.toml"])
    check(r.returncode == 2 and "/nonexistent.toml" in r.stderr, "a missing world is named", r)
    r = run([COORDINATORD, "--help"])
    check(r.returncode == 0 and "--socket" in r.stdout, "--help", r)
    with tempfile.TemporaryDirectory() as tmp:
        bad = os.path.join(tmp, "bad.toml")
        with open(bad, "w") as f:
            f.write('[sim]\nmodel = "pendulum"\nstep = "fast"\n')
        r = run([COORDINATORD, "--world", bad, "--socket", os.path.join(tmp, "s")])
        check(r.returncode == 2 and "bad.toml:3:" in r.stderr, "FILE:LINE for a bad scenario", r)
        r = run([TCS_RUN, "--connect", os.path.join(tmp, "none.sock"), "--", "/bin/true"])
        check(r.returncode == 2 and "no coordinatord there" in r.stderr, "no daemon: a clear error", r)
    with Daemon('[sim]\nmodel = "pendulum"\n') as d:
        r = run([COORDINATORD, "--world", d.world, "--socket", d.socket])
        check(r.returncode == 2 and "another coordinatord is serving there" in r.stderr, "one daemon per socket", r)
        for opt in (["-w", d.world], ["-m", "lockstep"], ["-d", "1s"], ["-t", "x.mcap"]):
            r = run([TCS_RUN, "--connect", d.socket] + opt + ["--", "/bin/true"])
            check(r.returncode == 2 and "cannot go with --connect" in r.stderr, "%s refused with --connect" % opt, r)
        r = run([TCS_RUN, "--connect", d.socket])
        check(r.returncode == 2 and "needs a PROGRAM" in r.stderr, "--connect without a program", r)


def test_sigterm_ends_the_daemon_cleanly():
    with Daemon('[sim]\nmodel = "pendulum"\n') as d:
        p = d.connect(PERIODIC, "--rate", 1000, "--seconds", 1000)
        d.wait_log(r"attached .*periodic_controller")
        time.sleep(0.5)
        check(d.stop() == 0, "exit 0 after SIGTERM\n" + d.log())
        d.wait_notice("STOPPING=1", 1)
        r = finish(p, 10, p.t0)
        # Its status is its own: it ended at SIGTERM, not at the SIGKILL
        # the 2 s grace would have sent.
        check(r.returncode == 0 and cycles_line(r)[0] > 0, "the controller got SIGTERM and reported", r)
        check(not os.path.exists(d.socket), "the socket is removed")
    counts = mcap_counts(d.trace)
    check(not counts["truncated"] and counts["topics"].get("/tcs/slice", 0) > 0, "the trace is closed whole: %s" % counts)


def test_ros2_tools_see_the_virtual_clock_on_dds():
    # A domain of this run's own: parallel runs must not hear each other.
    domain = 100 + os.getpid() % 100
    listeners = []
    for extra in ([], ["--joints"]):
        p = start([CLOCK_LISTEN, str(domain), "300", "30"] + extra, env=DDS_ENV)
        check(p.stdout.readline().strip() == "ready", "the subscriber is ready")
        p.t0 = time.monotonic()
        listeners.append(p)
    world = '[sim]\nmodel = "pendulum"\n[model]\ninitial_angle = 1.0\n'
    with Daemon(world, "--dds-domain", str(domain), env=DDS_ENV) as d:
        # With nobody attached the world steps at real-time speed: 1000
        # samples a second, which the listeners take in 0.3 s.
        clock, joints = [finish(p, 60, p.t0) for p in listeners]
        check(d.stop() == 0, "SIGTERM ends it\n" + d.log())
    check(clock.returncode == 0 and joints.returncode == 0, "both listeners got their samples", clock)
    lines = clock.stdout.splitlines()
    check(lines[0] == "type rosgraph_msgs::msg::dds_::Clock_", "the ROS 2 type name", clock)
    times = [int(l.split()[1]) * 10**9 + int(l.split()[2]) for l in lines[1:]]
    check(len(times) == 300, "300 samples", clock)
    # Each a step's time (a whole number of 1 ms steps), in order, none
    # twice. rt/clock keeps the last sample only (docs/DESIGN.md §7): one a
    # lagging reader has not taken yet is replaced by the next, so gaps are
    # the contract, not a fault.
    check(all(t % 10**6 == 0 for t in times) and all(b > a for a, b in zip(times, times[1:])),
          "every sample a 1 ms step's time, in order, none twice", clock)
    print("  300 clock samples over %.3f s of steps (%d steps left out by keep-last-1)" %
          ((times[-1] - times[0]) / 1e9, (times[-1] - times[0]) // 10**6 + 1 - 300))
    r = run([TCS_TRACE, "export", d.trace, "--format", "json"], timeout=120)
    check(r.returncode == 0, "the trace exports", r)
    messages = json.loads(r.stdout)["messages"]
    traced = {m["data"]["clock"]["sec"] * 10**9 + m["data"]["clock"]["nanosec"] for m in messages if m["topic"] == "/clock"}
    check(set(times) <= traced, "every time on rt/clock is a step of the trace")
    steps = {m["data"]["v_ns"]: dict(zip(m["data"]["joint_names"], m["data"]["joint_values"]))
             for m in messages if m["topic"] == "/tcs/step"}
    jl = joints.stdout.splitlines()
    check(jl[0] == "type sensor_msgs::msg::dds_::JointState_", "the JointState type name", joints)
    for line in jl[1:]:
        f = line.split()
        t = int(f[1]) * 10**9 + int(f[2])
        name, values = f[4].split("=")
        pos, vel = (float(x) for x in values.split(",")[:2])
        check(name == "pendulum.hinge", "the joint's name", joints)
        traced_pos = steps[t]["pendulum.hinge.position"]
        # Both print the double with 17 digits, which reads back exactly.
        check(pos == traced_pos, "joint state at %d as in the trace: %r, %r" % (t, pos, traced_pos), joints)


if __name__ == "__main__":
    main(globals())
