"""A world's host takes from its agents only finite commands to scalar
actuator signals within the step (docs/DESIGN.md §7): an agent is another
machine, and what it sends is untrusted. tests/programs/rogue_agent joins a
coordinatord's world over DDS as an agent would and answers every grant
with NaN and infinite efforts, a position, a pose, a signal the world
lacks, and efforts before and after the step; from one grant on, a finite
2 N*m effort first. The pendulum hangs at rest (θ = 0: no torque from
gravity), so the host's trace shows what was taken without tcs's word for
it: nothing moves until the good command, and then only as 2 N*m can move
it."""

import os

from daemon import DDS_ENV, Daemon
from harness import PROGRAMS, TCS_RUN, check, main, run, trace_rows

SCENARIOS = os.environ.get("TCS_SCENARIOS", "scenarios")
STEP_NS = 1000000
# The rod (1 kg, 1 m) about its hinge: m l^2 / 3.
INERTIA = 1.0 / 3


def signal_index(world, name):
    """Where a signal is in the world's table: tcs-run --list-signals lists
    them in its order."""
    r = run([TCS_RUN, "--list-signals", "-w", world])
    check(r.returncode == 0, "--list-signals", r)
    names = [line.split()[0] for line in r.stdout.split("devices\n")[0].splitlines()[1:]]
    check(name in names, "%s among the signals %s" % (name, names), r)
    return names.index(name)


def test_the_host_takes_only_finite_scalar_commands_within_the_step():
    domain = 200 + os.getpid() % 30  # (apart from test_daemon's 100-199 and test_agents' 150-199)
    world = os.path.join(SCENARIOS, "pendulum.toml")
    effort = signal_index(world, "pendulum.hinge.effort")
    position = signal_index(world, "pendulum.hinge.position")
    pose = signal_index(world, "pendulum.rod.pose")
    with open(world) as f:
        text = f.read()
    with Daemon(text, "--dds-domain", str(domain), env=DDS_ENV) as host:
        agent = run([os.path.join(PROGRAMS, "rogue_agent"), domain, "rogue", STEP_NS, effort, position, pose, 100, 300],
                    timeout=60, env=DDS_ENV)
        check(agent.returncode == 0 and "answered=300" in agent.stdout, "the rogue agent answers 300 grants", agent)
        host.wait_log(r"agent rogue has left")
        check("agent rogue sent a command the world cannot take" in host.log(), "the host says it refused them\n" +
              host.log())
        check(host.stop() == 0, "the host ends cleanly\n" + host.log())
        steps = trace_rows(host.trace, "/tcs/step")
    good_at = int(agent.values()["good_at"])
    rows = [(int(x["v_ns"]), float(x["joint.pendulum.hinge.position"]), float(x["joint.pendulum.hinge.velocity"]))
            for x in steps]
    before = [r for r in rows if r[0] <= good_at]
    after = [r for r in rows if good_at < r[0] <= good_at + 50 * STEP_NS]
    check(len(before) > 100 and all(p == 0 and w == 0 for _, p, w in before),
          "at rest until the good command: none of the bad ones moved it (%d steps)" % len(before))
    check(len(after) == 50, "50 steps after it", after[:3])
    # Written a quarter into the step after good_at, it acts from that
    # step's end (zero-order hold): moving by the step after. 2 N*m on the
    # rod at rest accelerates it at 2 / I at most (gravity only holds it
    # back): a 5 N*m effort (the commands outside the step) or an infinite
    # one would exceed that, a NaN would not be a number.
    for v, p, w in after:
        t = (v - good_at) / 1e9
        moving = v >= good_at + 2 * STEP_NS
        check((w > 0 if moving else w >= 0) and w <= 2.0 / INERTIA * t,
              "at %d ns: velocity %r, at most %.6f from 2 N*m" % (v, w, 2.0 / INERTIA * t))
    print("  %d steps at rest under NaN, inf, a position, a pose, an unknown signal and out-of-step efforts; "
          "then %.4f rad/s 50 ms after 2 N*m" % (len(before), after[-1][2]))


if __name__ == "__main__":
    main(globals())
