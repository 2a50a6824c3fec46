"""meson install into any prefix gives a tcs-run that finds its own
preload library, tcs-trace, their man pages and the protocol headers."""

import glob
import os
import shutil
import tempfile

from harness import check, main, run

BUILD = os.environ.get("TCS_BUILD_ROOT", "build")
MESON = os.environ.get("TCS_MESON", "meson")


def test_installed_tcs_run_finds_its_preload():
    root = tempfile.mkdtemp(prefix="tcs-install-")
    try:
        r = run([MESON, "install", "-C", BUILD, "--no-rebuild", "--destdir", root], timeout=120)
        check(r.returncode == 0, "meson install succeeds", r)
        found = glob.glob(os.path.join(root, "**", "bin", "tcs-run"), recursive=True)
        check(len(found) == 1, "one tcs-run installed: %s" % found)
        tcs_run = found[0]
        # TCS_PRELOAD="" : no help from the environment or the build tree.
        r = run([tcs_run, "-q", "-m", "lockstep", "--", "sh", "-c", 'sleep 2; echo "$LD_PRELOAD"'],
                env={"TCS_PRELOAD": ""})
        check(r.returncode == 0, "the installed tcs-run runs a controller", r)
        check(r.stdout.strip().startswith(root) and r.stdout.strip().endswith("/tcs/libtcs_preload.so"),
              "with the installed preload library", r)
        for page in ("tcs-run.1", "tcs-trace.1"):
            check(glob.glob(os.path.join(root, "**", "man1", page), recursive=True), "the man page " + page)
        tools = glob.glob(os.path.join(root, "**", "bin", "tcs-trace"), recursive=True)
        check(len(tools) == 1, "tcs-trace installed")
        r = run([tools[0], "--version"])
        check(r.returncode == 0 and r.stdout.startswith("tcs-trace "), "and it runs", r)
        check(glob.glob(os.path.join(root, "**", "include", "tcs", "protocol.h"), recursive=True), "headers")
        check(glob.glob(os.path.join(root, "**", "include", "tcs", "simhost.h"), recursive=True),
              "the simulation plug-in ABI")
        check(glob.glob(os.path.join(root, "**", "share", "tcs", "scenarios", "pendulum.toml"), recursive=True),
              "the scenario files")
        pc = glob.glob(os.path.join(root, "**", "pkgconfig", "tcs-simhost.pc"), recursive=True)
        check(len(pc) == 1, "and its pkg-config file")
        with open(pc[0]) as f:
            check("Cflags: -I${includedir}" in f.read(), "which points at the headers")
    finally:
        shutil.rmtree(root, ignore_errors=True)


if __name__ == "__main__":
    main(globals())
