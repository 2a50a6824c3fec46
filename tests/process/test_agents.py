"""Controllers on another host (docs/DESIGN.md §7): coordinatord --agent, in a
network namespace of its own joined to the host's by a veth pair (the test
makes both; where namespaces are not permitted, each test runs on loopback and
is then reported as skipped, naming why), runs a
controller for a world its host steps, through the step protocol over DDS.
The pendulum experiment comes out as it does in-process, and an agent that
dies stops the world with a clear error within DDS's liveliness lease."""

import contextlib
import os
import signal
import subprocess
import time

from daemon import DDS_ENV, EXAMPLES, Daemon, mcap_counts
from harness import TCS_RUN, check, finish, main, need_tool, run, skip

PENDULUM_PD = os.path.join(EXAMPLES, "pendulum_pd")
SCENARIOS = os.environ.get("TCS_SCENARIOS", "scenarios")


def dds_uri(own, peer):
    """Cyclone on one interface, finding its peer by unicast."""
    return {"CYCLONEDDS_URI": '<General><Interfaces><NetworkInterface address="%s"/></Interfaces>'
            '<AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto'
            '</ParticipantIndex><Peers><Peer address="%s"/></Peers></Discovery>' % (own, peer)}


class Hosts:
    """A second host: a network namespace with a veth to this one. Falls
    back to loopback where namespaces are not permitted (`loopback` says
    why; apart() then skips the test, whose checks passed on one host)."""

    def __enter__(self):
        need_tool("ip", "iproute2")
        n = os.getpid() % 250 + 1
        self.ns = "tcs-test-%d" % os.getpid()
        here, there = "10.201.%d.1" % n, "10.201.%d.2" % n
        veth = "tcsv%d" % os.getpid()
        steps = [["ip", "netns", "add", self.ns],
                 ["ip", "link", "add", veth, "type", "veth", "peer", "name", veth + "b"],
                 ["ip", "link", "set", veth + "b", "netns", self.ns],
                 ["ip", "addr", "add", here + "/30", "dev", veth],
                 ["ip", "link", "set", veth, "up"],
                 ["ip", "netns", "exec", self.ns, "ip", "addr", "add", there + "/30", "dev", veth + "b"],
                 ["ip", "netns", "exec", self.ns, "ip", "link", "set", veth + "b", "up"],
                 ["ip", "netns", "exec", self.ns, "ip", "link", "set", "lo", "up"]]
        self.made = False
        self.loopback = None
        for cmd in steps:
            try:
                r = subprocess.run(cmd, capture_output=True, text=True)
                why = r.stderr.strip() if r.returncode != 0 else None
            except FileNotFoundError:
                why = "no ip command (iproute2)"
            if why is not None:
                self.loopback = "no network namespace (%s: %s)" % (" ".join(cmd), why)
                print("  %s: the agent runs on loopback" % self.loopback)
                self.cleanup()
                self.host_env, self.agent_env, self.prefix = DDS_ENV, DDS_ENV, []
                return self
            self.made = True
        self.host_env, self.agent_env = dds_uri(here, there), dds_uri(there, here)
        self.prefix = ["ip", "netns", "exec", self.ns]
        return self

    def cleanup(self):
        if self.made:
            subprocess.run(["ip", "netns", "del", self.ns], capture_output=True)  # its veth goes with it
            self.made = False

    def __exit__(self, *exc):
        self.cleanup()

    def apart(self):
        """After a test's checks: on loopback, they were not made across two
        hosts, which is what the test is for."""
        if self.loopback:
            skip("%s: its checks passed on loopback, not across two hosts" % self.loopback)


def pendulum_world(expects=False):
    """The built-in world, written out; expecting pendulum_pd, or nobody."""
    with open(os.path.join(SCENARIOS, "pendulum.toml")) as f:
        return f.read() + ('\n[[controller]]\ncommand = "pendulum_pd"\n' if expects else "")


def agent_args(domain):
    return ["--agent", "--dds-domain", str(domain), "--name", "far"]


def test_an_agent_runs_the_pendulum_as_in_process():
    domain = 150 + os.getpid() % 50
    world = pendulum_world(expects=True)
    alone = run([TCS_RUN, "-q", "-m", "lockstep", "--", PENDULUM_PD, "--seconds", "5"])
    check(alone.returncode == 0 and "balanced=1" in alone.stdout, "in-process: balanced", alone)
    with Hosts() as hosts:
        with Daemon(world, "--mode", "lockstep", "--dds-domain", str(domain), env=hosts.host_env) as host:
            with Daemon(None, *agent_args(domain), env=hosts.agent_env, prefix=hosts.prefix) as agent:
                host.wait_log(r"agent far has joined", timeout=20)
                p = agent.connect(PENDULUM_PD, "--seconds", 5, opts=["-q"])
                far = finish(p, 120, p.t0)
                check(agent.stop() == 0, "the agent ends cleanly\n" + agent.log())
            host.wait_log(r"agent far has left")
            check("1 of 1 expected" in host.log() and "the world runs" in host.log(),
                  "the host waited for the agent's controller\n" + host.log())
            check(host.stop() == 0, "the host ends cleanly\n" + host.log())
    check(far.returncode == 0 and "balanced=1" in far.stdout, "through the agent: balanced", far)
    check(far.values() == alone.values(), "the same outcome, figure for figure:\n%s\n%s" % (alone.stdout, far.stdout))
    hosts.apart()


@contextlib.contextmanager
def pendulum_on_an_agent(hosts, domain):
    """A host, an agent that has joined it, and a long pendulum run there
    (its tcs-run started): (host, agent, tcs-run)."""
    with Daemon(pendulum_world(), "--dds-domain", str(domain), env=hosts.host_env) as host:
        with Daemon(None, *agent_args(domain), env=hosts.agent_env, prefix=hosts.prefix) as agent:
            host.wait_log(r"agent far has joined", timeout=20)
            p = agent.connect(PENDULUM_PD, "--seconds", 1000)
            agent.wait_log(r"attached .*pendulum_pd")
            time.sleep(0.5)
            yield host, agent, p


def kill_and_wait_for(victim, survivor, said):
    """SIGKILL to one side; the other must say so and end by itself.
    Returns how long the saying took."""
    t0 = time.monotonic()
    victim.proc.send_signal(signal.SIGKILL)
    victim.proc.wait()
    survivor.wait_log(said, timeout=10)
    took = time.monotonic() - t0
    try:
        survivor.proc.wait(10)
    except subprocess.TimeoutExpired:
        raise AssertionError("it runs on without its peer\n" + survivor.log())
    return took


def test_a_lost_agent_stops_the_world():
    domain = 150 + (os.getpid() + 25) % 50
    with Hosts() as hosts:
        with pendulum_on_an_agent(hosts, domain) as (host, agent, p):
            took = kill_and_wait_for(agent, host, r"agent far is gone")
            client = finish(p, 30, p.t0)
            check(host.proc.returncode == 2, "the host ends with an error\n" + host.log())
            last = host.log().strip().splitlines()[-1]
            check(last.startswith("coordinatord: agent far is gone (no sign of life for 1000 ms): the world stops"),
                  "a clear error naming the agent: %r" % last)
            # The lease is 1 s from the agent's last message (sent before
            # the SIGKILL); Cyclone's gc thread sleeps until a lease's end
            # (no polling between), then the host's listener, event loop
            # and log line follow, and this test looks at the log every
            # 20 ms. Allowed for the host's threads to get a core on this
            # shared VM: a quarter of the lease (the longest pause seen in
            # these tests is 5.7 ms).
            print("  the loss was seen %.3f s after the agent died" % took)
            check(took <= 1.0 + 0.02 + 0.25, "seen at the lease's end: %.3f s" % took)
    check(client.returncode == 2 and "went away" in client.stderr, "its tcs-run is told", client)
    counts = mcap_counts(host.trace)
    check(not counts["truncated"], "the host's trace is closed whole: %s" % counts)
    hosts.apart()


def test_an_agent_whose_host_is_lost_ends_its_controllers():
    domain = 150 + (os.getpid() + 12) % 50
    with Hosts() as hosts:
        with pendulum_on_an_agent(hosts, domain) as (host, agent, p):
            kill_and_wait_for(host, agent, r"the world's host is gone")
            client = finish(p, 30, p.t0)
            check(agent.proc.returncode == 2, "the agent ends with an error\n" + agent.log())
            check("its controllers here are ended" in agent.log().strip().splitlines()[-1], "a clear last word\n" +
                  agent.log())
    # pendulum_pd ends its loop on SIGTERM and reports: its own status.
    check(client.returncode == 0 and "cycles=" in client.stdout, "the controller was ended and reported", client)
    hosts.apart()


if __name__ == "__main__":
    main(globals())
