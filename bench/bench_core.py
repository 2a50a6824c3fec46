"""What every group of bench/run.py's figures stands on: running the
build's programs (and reading the figures they print), interleaved rounds
whose medians are compared, and one row of the table."""

import os
import re
import statistics
import subprocess
import tempfile
import time


class Bench:
    def __init__(self, build, quick):
        self.build = build
        self.quick = quick
        self.rounds = 3 if quick else 7
        self.tmp = tempfile.mkdtemp(prefix="tcs-bench-")

    def path(self, *parts):
        return os.path.join(self.build, *parts)

    def run(self, args, env=None, timeout=600):
        full = dict(os.environ)
        full.update(env or {})
        t0 = time.monotonic()
        r = subprocess.run([str(a) for a in args], capture_output=True, text=True, env=full, timeout=timeout,
                           stdin=subprocess.DEVNULL)
        wall = time.monotonic() - t0
        if r.returncode != 0:
            raise RuntimeError("%s failed (exit %d): %s" % (" ".join(map(str, args)), r.returncode,
                                                            (r.stderr or r.stdout)[-500:]))
        return r, wall

    def values(self, args, env=None):
        r, _ = self.run(args, env)
        return {k: float(v) for k, v in re.findall(r"([A-Za-z_]\w*)=([-0-9.e+]+)", r.stdout)}

    def tcs(self, *args):
        return [self.path("tools", "tcs-run")] + list(args)

    def interleaved(self, makers):
        """Runs each (name, fn) once per round, interleaved; the median of each."""
        got = {name: [] for name, _ in makers}
        for _ in range(self.rounds):
            for name, fn in makers:
                got[name].append(fn())
        return {name: statistics.median(v) for name, v in got.items()}, got


def row(name, tcs, unit, baseline, baseline_name, ratio, target, ok, note=""):
    return {"figure": name, "tcs": tcs, "unit": unit, "baseline": baseline, "baseline_name": baseline_name,
            "ratio": ratio, "target": target, "meets_target": ok, "note": note}
