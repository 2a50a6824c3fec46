"""coordinatord for the process tests: a daemon serving a world from a
temporary folder, ready when it says READY=1 on its NOTIFY_SOCKET (as
systemd would hear it), and what tests read back from it."""

import json
import os
import re
import signal
import socket
import subprocess
import tempfile
import time

from harness import TCS_RUN, TCS_TRACE, assert_nothing_left, check, demote, read_trace, run, start

COORDINATORD = os.environ.get("TCS_COORDINATORD", "coordinatord")
EXAMPLES = os.environ.get("TCS_EXAMPLES", "examples")
PERIODIC = os.path.join(EXAMPLES, "periodic_controller")
CLOCK_LISTEN = os.environ.get("TCS_CLOCK_LISTEN", "clock_listen")
# DDS on loopback alone (CI machines may have no other interface; no
# multicast there): unicast discovery among the participants on this host.
DDS_ENV = {"CYCLONEDDS_URI": '<General><Interfaces><NetworkInterface name="lo"/></Interfaces>'
           '<AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex>'
           '<Peers><Peer address="127.0.0.1"/></Peers></Discovery>'}


class Daemon:
    """coordinatord serving a world from a temporary folder; ready when it
    says READY=1 on its NOTIFY_SOCKET, as systemd would hear it."""

    def __init__(self, world, *args, env=None, prefix=()):
        """world: the scenario's text (None for an agent, which has its
        host's); prefix: a command to run it under (ip netns exec NS)."""
        self.dir = tempfile.mkdtemp(prefix="tcs-test-daemon-")
        self.world = os.path.join(self.dir, "world.toml") if world is not None else None
        if world is not None:
            with open(self.world, "w") as f:
                f.write(world)
        self.prefix = list(prefix)
        self.socket = os.path.join(self.dir, "coordinatord.sock")
        self.trace = os.path.join(self.dir, "world.mcap")
        self.args = list(args)
        self.env = env or {}
        self.notified = []

    def __enter__(self):
        self.notify = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
        self.notify.bind(os.path.join(self.dir, "notify"))
        self.log_path = os.path.join(self.dir, "log")
        self.log_file = open(self.log_path, "w")
        env = dict(os.environ, NOTIFY_SOCKET=os.path.join(self.dir, "notify"), **self.env)
        self.proc = subprocess.Popen(
            self.prefix + [COORDINATORD, "--socket", self.socket] +
            (["--world", self.world, "--trace", self.trace] if self.world else []) + self.args,
            stdin=subprocess.DEVNULL, stdout=self.log_file, stderr=subprocess.STDOUT, env=env,
            start_new_session=True, cwd=self.dir)
        self.wait_notice("READY=1", 10)
        return self

    def wait_notice(self, what, timeout):
        deadline = time.monotonic() + timeout
        while not any(what in n for n in self.notified):
            # What it sent before it exited is still queued: read on.
            ended = self.proc.poll() is not None
            left = deadline - time.monotonic()
            self.notify.settimeout(max(min(left, 0.2), 0.001))
            try:
                self.notified.append(self.notify.recv(4096).decode())
            except socket.timeout:
                check(left > 0 and not ended,
                      "coordinatord says %s (exit %s)\n%s" % (what, self.proc.poll(), self.log()))

    def log(self):
        with open(self.log_path) as f:
            return f.read()

    def wait_log(self, pattern, timeout=10):
        deadline = time.monotonic() + timeout
        while True:
            ended = self.proc.poll() is not None  # what it wrote before it ended is read next
            if re.search(pattern, self.log()):
                return
            check(time.monotonic() < deadline and not ended, "coordinatord logs %r\n%s" % (pattern, self.log()))
            time.sleep(0.02)

    def connect(self, *program, opts=(), env=None, cwd=None):
        """tcs-run --connect [opts] -- program..., started (not waited for)."""
        p = start([TCS_RUN, "--connect", self.socket] + list(opts) + ["--"] + [str(a) for a in program], env=env)
        p.t0 = time.monotonic()
        return p

    def controller_pids(self):
        return [int(p) for p in re.findall(r"attached .* \(pid (\d+)\)", self.log())]

    def stop(self, timeout=15):
        self.proc.send_signal(signal.SIGTERM)
        try:
            self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            demote(self.proc.pid)
            os.killpg(self.proc.pid, signal.SIGKILL)
            self.proc.wait()
            raise AssertionError("coordinatord did not end within %ss of SIGTERM\n%s" % (timeout, self.log()))
        return self.proc.returncode

    def __exit__(self, *exc):
        if self.proc.poll() is None:
            self.stop()
        self.log_file.close()
        self.notify.close()
        assert_nothing_left(self.proc.pid)
        for pid in self.controller_pids():
            check(not os.path.exists("/proc/%d" % pid) or open("/proc/%d/stat" % pid).read().split(") ")[1][0] == "Z",
                  "controller %d is gone" % pid)


def cycles_line(r):
    """periodic_controller's own report: (cycles, rate, misses)."""
    m = re.search(r"(\d+) cycles in [\d.]+ s: ([\d.]+) Hz \(asked for [\d.]+ Hz\), (\d+) deadline misses", r.stdout)
    check(m is not None, "the controller reports its loop", r)
    return int(m.group(1)), float(m.group(2)), int(m.group(3))


def trace_summary(path):
    r = run([TCS_TRACE, "summary", "--json", path])
    check(r.returncode == 0, "tcs-trace summary reads the daemon's trace", r)
    return json.loads(r.stdout)


def mcap_counts(path):
    return read_trace(path, complete=False)
