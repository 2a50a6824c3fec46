"""The TCS paper's experiment: a 1 kHz swing-up and balance controller.
With light work it balances in cpu mode. With work its loop cannot afford
on a slower target CPU it falls far below its rate and the pendulum falls,
in cpu mode as on the robot, while lockstep (how simulators run
controllers today) reports success for the same binary and the same work."""

import os

from harness import check, main, tcs

PD = os.path.join(os.environ.get("TCS_EXAMPLES", "."), "pendulum_pd")


def outcome(tcs_args, program_args):
    r = tcs("-q", *tcs_args, "--", PD, "--seconds", "10", *program_args, timeout=180)
    check(r.returncode == 0, "pendulum_pd runs to its end", r)
    v = r.values()
    return r, v, "%s (%s Hz, %s misses, %.3f rad from upright at worst in the last 2 s)" % (
        "BALANCED" if v["balanced"] == "1" else "FELL", v["rate_hz"], v["misses"], float(v["worst_last2s"]))


def test_light_controller_balances():
    r, v, text = outcome(["-m", "cpu"], ["--work-us", "50"])
    print("  cpu mode, 50 us of work per cycle: " + text)
    check(v["balanced"] == "1" and float(v["worst_last2s"]) < 0.1, "within 0.1 rad of upright", r)
    check(abs(float(v["rate_hz"]) - 1000) < 20, "at its rate", r)


def test_overloaded_controller_falls_but_lockstep_says_fine():
    # 300 us of this CPU's work per cycle, on a target 6 times slower: 1.8 ms
    # of work in a 1 ms period.
    r, cpu, text = outcome(["-m", "cpu", "--cpu-scale", "6"], ["--work-us", "300"])
    print("  cpu mode, 300 us of work on a CPU 6x slower: " + text)
    check(float(cpu["rate_hz"]) < 700, "the loop falls far below its rate", r)
    check(cpu["balanced"] == "0", "and the pendulum falls, as it would on the robot", r)
    r, lock, text = outcome(["-m", "lockstep", "--cpu-scale", "6"], ["--work-us", "300"])
    print("  lockstep, the same binary and work:          " + text)
    check(lock["balanced"] == "1" and abs(float(lock["rate_hz"]) - 1000) < 1, "lockstep reports success", r)


if __name__ == "__main__":
    main(globals())
