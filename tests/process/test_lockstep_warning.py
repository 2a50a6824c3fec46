"""Lockstep's warning (tcs-run(1), LIMITATIONS): in lockstep virtual time
cannot advance for a program that computes without ever waiting, and
tcs-run warns once the program has computed for 10 seconds without a wait.
The CPU is the kernel's (tests/programs/compute.c reads it with a raw
system call): 10.5 s straight is warned of once; 11 s in two halves with
a sleep between is not (each half is under 10 s since the last wait)."""

from harness import check, main, prog, tcs

WARNING = "in lockstep mode virtual time advances only when controllers wait, and '%s' has computed for 10 s " \
          "without waiting"


def test_ten_seconds_without_a_wait_are_warned_of_once():
    r = tcs("-m", "lockstep", prog("compute"), "10.5", timeout=120)
    check(r.returncode == 0, "the program runs to its end", r)
    check(r.stderr.count("tcs-run: warning: " + WARNING % prog("compute")) == 1,
          "10.5 s of CPU without a wait: warned once", r)


def test_computing_between_waits_is_not_warned_of():
    r = tcs("-m", "lockstep", prog("compute"), "5.5", "5.5", timeout=120)
    check(r.returncode == 0, "the program runs to its end", r)
    check("has computed for 10 s" not in r.stderr, "11 s of CPU in two halves with a sleep between: no warning", r)


if __name__ == "__main__":
    main(globals())
