"""tcs-run's exit status (tcs-run(1), EXIT STATUS; docs/DESIGN.md §5): with
several programs, that of the first of them in the scenario's order that
did not exit 0 (not the first to end), 128+N for one a signal N killed, and
127 for a program that could not be executed: one tcs-run let through (it
passes every check) whose exec fails in the kernel."""

import os
import shutil
import tempfile

from harness import check, main, prog, scenario_file, skip, tcs

WORLD = """\
[sim]
step = "1ms"

[[model]]
name = "pendulum"
type = "pendulum"
"""

# The dynamic loader every x86-64 program of this system names (PT_INTERP).
LOADER = b"/lib64/ld-linux-x86-64.so.2"


def controllers(*commands):
    return WORLD + "".join('[[controller]]\ncommand = "%s"\n' % c for c in commands)


def run_world(*commands):
    with scenario_file(controllers(*commands)) as world:
        return tcs("-q", "-m", "lockstep", "-w", world, timeout=60)


def test_the_first_failing_program_in_scenario_order_decides():
    # The second in the file fails last (after 2 s), the third first (at
    # once): the second's status is tcs-run's.
    r = run_world("sh -c 'exit 0'", "sh -c 'sleep 2; exit 3'", "sh -c 'exit 5'")
    check(r.returncode == 3, "exit 3 of the second program, not 5 of the third that ended first", r)
    # A signal's death counts as 128+N in its place.
    r = run_world("sh -c 'exit 0'", "sh -c 'sleep 2; kill -SEGV $$'", "sh -c 'exit 5'")
    check(r.returncode == 128 + 11, "128+11 of the second, killed by SIGSEGV after the third's exit 5", r)
    # Programs that exited 0 are passed over, wherever they are.
    r = run_world("sh -c 'sleep 1; exit 0'", "sh -c 'exit 0'", "sh -c 'sleep 2; exit 6'")
    check(r.returncode == 6, "exit 6 of the third, the only one that failed", r)
    r = run_world("sh -c 'exit 0'", "sh -c 'sleep 1'")
    check(r.returncode == 0, "every program exited 0: exit 0", r)


def test_a_program_that_cannot_be_executed_exits_127():
    # An ELF program whose loader is missing: it passes tcs-run's checks
    # (64-bit, this machine's, dynamic), and the kernel's execve fails
    # (ENOENT, for its interpreter).
    d = tempfile.mkdtemp(prefix="tcs-test-exit-")
    try:
        path = os.path.join(d, "no_loader")
        with open(prog("exit_with"), "rb") as f:
            data = f.read()
        if data.count(LOADER) != 1:
            skip("exit_with does not name %s once (not an x86-64 glibc system)" % LOADER.decode())
        with open(path, "wb") as f:
            f.write(data.replace(LOADER, LOADER[:-1] + b"9"))
        os.chmod(path, 0o755)
        check(not os.path.exists((LOADER[:-1] + b"9").decode()), "the loader it names is not there")
        r = tcs("-q", path, "0", timeout=30)
        check(r.returncode == 127, "exit 127 for a program that cannot be executed", r)
        check("cannot execute " + path in r.stderr, "and why, with its path", r)
        # In a scenario, in its place: the first program's exit 4 comes
        # first; after one that exited 0, the 127 is the run's.
        r = run_world("sh -c 'sleep 1; exit 4'", path + " 0")
        check(r.returncode == 4, "the first program's exit 4 before the second's 127", r)
        r = run_world("sh -c 'exit 0'", path + " 0")
        check(r.returncode == 127, "127 of the second, the first having exited 0", r)
    finally:
        shutil.rmtree(d)


if __name__ == "__main__":
    main(globals())
