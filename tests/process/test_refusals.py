"""Programs tcs-run refuses before they start (tcs-run(1), LIMITATIONS;
docs/DESIGN.md §3): 32-bit programs, programs for another architecture,
and set-user-ID or set-group-ID programs that would change the user or
group, since the loader would not load the hooks and the program would run
in real time: exit 2 and one line naming the cause. A #! script is run, and
its interpreter is what is checked (tcs-run(1), DESCRIPTION): a script
whose interpreter is refusable is refused for its interpreter's sake.

The refused ELF files are made here from a program of ours with its header
patched (no 32-bit or foreign toolchain is needed: the refusal reads the
header, and the kernel could not run such a file on this machine anyway,
so a tcs-run that let one through fails with 127 instead of 2)."""

import contextlib
import os
import shutil
import tempfile

from harness import PYTHON, check, main, prog, skip, tcs

# ELF header fields (the System V ABI's gABI, elf(5)).
EI_CLASS = 4
ELFCLASS32 = 1
E_MACHINE = 18  # a little-endian Elf64_Half after e_ident (16) and e_type (2)
EM_AARCH64 = 183
EM_X86_64 = 62
NOBODY = 65534


@contextlib.contextmanager
def scratch():
    """A directory of its own for the files a test makes."""
    d = tempfile.mkdtemp(prefix="tcs-test-refusals-")
    try:
        yield d
    finally:
        shutil.rmtree(d)


def patched_copy(d, name, offset, value):
    """exit_with copied to d/name with one byte (offset) or the machine
    (E_MACHINE: two bytes) replaced."""
    path = os.path.join(d, name)
    shutil.copy(prog("exit_with"), path)
    with open(path, "r+b") as f:
        data = bytearray(f.read())
        check(data[:4] == b"\x7fELF" and data[E_MACHINE:E_MACHINE + 2] == EM_X86_64.to_bytes(2, "little"),
              "the program patched is an x86-64 ELF file")
        if offset == E_MACHINE:
            data[E_MACHINE:E_MACHINE + 2] = value.to_bytes(2, "little")
        else:
            data[offset] = value
        f.seek(0)
        f.write(data)
    return path


def script(d, name, text):
    path = os.path.join(d, name)
    with open(path, "w") as f:
        f.write(text)
    os.chmod(path, 0o755)
    return path


def refused(args, cause, what):
    """tcs-run ARGS exits 2 with one line, tcs-run's, naming cause; the
    program (exit_with 7) did not run, or its status would be 7."""
    r = tcs(*args, timeout=30)
    check(r.returncode == 2, "%s: refused with exit 2" % what, r)
    lines = r.stderr.strip().splitlines()
    check(len(lines) == 1 and lines[0].startswith("tcs-run: ") and cause in lines[0],
          "%s: one line naming the cause ('%s')" % (what, cause), r)
    return r


def test_32_bit_and_foreign_programs_are_refused():
    with scratch() as d:
        elf32 = patched_copy(d, "elf32", EI_CLASS, ELFCLASS32)
        refused([elf32, "7"], elf32 + " is a 32-bit program", "a 32-bit program")
        arm = patched_copy(d, "arm64", E_MACHINE, EM_AARCH64)
        refused([arm, "7"], arm + " is built for another architecture", "an aarch64 program")
        # The copy unpatched runs: the refusals are the header's doing.
        plain = patched_copy(d, "plain", EI_CLASS, 2)  # ELFCLASS64, as it was
        r = tcs("-q", plain, "7", timeout=30)
        check(r.returncode == 7, "the same program unpatched runs (its exit 7 passes through)", r)


def test_set_id_programs_that_change_user_or_group_are_refused():
    if os.geteuid() != 0:
        skip("giving a program to another user (chown) needs root")
    with scratch() as d:
        os.chmod(d, 0o755)
        setuid = patched_copy(d, "setuid", EI_CLASS, 2)
        os.chown(setuid, NOBODY, -1)
        os.chmod(setuid, 0o4755)
        refused([setuid, "7"], "is set-user-ID or set-group-ID", "a set-user-ID program of another user")
        setgid = patched_copy(d, "setgid", EI_CLASS, 2)
        os.chown(setgid, -1, NOBODY)
        os.chmod(setgid, 0o2755)
        if os.getegid() != NOBODY:
            refused([setgid, "7"], "is set-user-ID or set-group-ID", "a set-group-ID program of another group")
        # Set-user-ID to oneself changes nothing: the loader keeps LD_PRELOAD,
        # so it runs under tcs.
        own = patched_copy(d, "own", EI_CLASS, 2)
        os.chown(own, os.geteuid(), os.getegid())
        os.chmod(own, 0o6755)
        r = tcs("-q", own, "7", timeout=30)
        check(r.returncode == 7, "a set-ID program of one's own user and group runs", r)


def test_scripts_run_and_their_interpreter_is_checked():
    with scratch() as d:
        # A #! script runs, under tcs: a 3 s sleep of Python found through
        # env lasts 3 s and its timer slack (50 us: docs/DESIGN.md §2) in
        # lockstep, exactly, in well under 3 s of wall time.
        py = script(d, "sleeper", "#!/usr/bin/env %s\nimport time\nt = time.monotonic_ns()\n"
                    "time.sleep(3)\nprint('slept_ns=%%d' %% (time.monotonic_ns() - t))\n" % os.path.basename(PYTHON))
        env = dict(os.environ, PATH=os.path.dirname(PYTHON) + os.pathsep + os.environ.get("PATH", ""))
        r = tcs("-q", "-m", "lockstep", "--spin-cost", "0", py, timeout=30, env=env)
        check(r.returncode == 0 and r.values().get("slept_ns") == str(3 * 10**9 + 50000),
              "a #!/usr/bin/env script runs in virtual time: 3 s + 50 us", r)
        check(r.wall < 3, "and in less wall time than it slept (%.2f s)" % r.wall, r)
        sh = script(d, "seven", "#!/bin/sh\nexit 7\n")
        check(tcs("-q", sh, timeout=30).returncode == 7, "a #!/bin/sh script's exit 7 passes through")
        # Its interpreter refusable: the script is refused, naming it.
        elf32 = patched_copy(d, "elf32", EI_CLASS, ELFCLASS32)
        refused([script(d, "on32", "#!%s 7\n" % elf32)], elf32 + " is a 32-bit program",
                "a script of a 32-bit interpreter")
        arm = patched_copy(d, "arm64", E_MACHINE, EM_AARCH64)
        refused([script(d, "onarm", "#! %s\n" % arm)], arm + " is built for another architecture",
                "a script of a foreign interpreter ('#! ' with a space)")
        static = prog("static_hello")
        refused([script(d, "onstatic", "#!%s\n" % static)], "statically linked",
                "a script of a static interpreter")
        # Through a script that is itself an interpreter, and through env.
        refused([script(d, "nested", "#!%s\n" % script(d, "middle", "#!%s\n" % elf32))],
                elf32 + " is a 32-bit program", "a script whose interpreter is a script of a 32-bit one")
        envd = dict(os.environ, PATH=d + os.pathsep + os.environ.get("PATH", ""))
        r = tcs(script(d, "viaenv", "#!/usr/bin/env arm64\n"), timeout=30, env=envd)
        check(r.returncode == 2 and "is built for another architecture" in r.stderr,
              "a #!/usr/bin/env script's interpreter, found in PATH, is checked", r)
        refused([script(d, "noprog", "#!/usr/bin/env -S\n")], "names no program", "#!/usr/bin/env naming nothing")


if __name__ == "__main__":
    main(globals())
