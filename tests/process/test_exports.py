"""libtcs_preload exports exactly its hooks (libtcs_preload/exports.txt):
anything else it exported could interpose on the program by accident."""

import os
import subprocess

from harness import check, main

SO = os.environ.get("TCS_PRELOAD_SO", "libtcs_preload.so")
LIST = os.environ.get("TCS_EXPORTS", "exports.txt")


def test_exports_match_the_intended_list():
    nm = subprocess.run(["nm", "-D", "--defined-only", SO], capture_output=True, text=True, check=True)
    exported = {line.split()[-1] for line in nm.stdout.splitlines() if line.strip()}
    with open(LIST) as f:
        intended = {line.strip() for line in f if line.strip() and not line.startswith("#")}
    check(exported == intended, "unexpected exports: %s; missing: %s" %
          (sorted(exported - intended), sorted(intended - exported)))


def test_no_undefined_symbols_beyond_libc():
    nm = subprocess.run(["nm", "-D", "--undefined-only", SO], capture_output=True, text=True, check=True)
    bad = [line for line in nm.stdout.splitlines() if "@GLIBC" not in line and line.strip()
           and not line.strip().startswith("w ")]
    check(not bad, "libtcs_preload needs only libc: %s" % bad)


if __name__ == "__main__":
    main(globals())
