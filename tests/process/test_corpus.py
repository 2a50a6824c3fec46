"""The idiom corpus (issue 35, docs/DESIGN.md §10): the idioms program
makes each hooked call from main, a second thread, a signal handler
interrupting another hooked call, a nested handler, a fork child of a
threaded program and a vfork child; tests/corpus/idioms.py does the same
for a few Python idioms. The suite runs a fixed sample of the product
(tests/corpus/cases.py: every call, context and interrupted call at least
once) natively and in both modes, each run judged by the program's own
checks, against its native run and by the contract
(tests/corpus/run_corpus.py); `tests/corpus/run_corpus.py --all` runs the
whole product by hand."""

import os
import re
import sys
import time

from harness import check, main

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "corpus"))
import cases  # noqa: E402
import run_corpus  # noqa: E402

BUDGET = 240

# Defects the corpus has found and tcs still has, each a pattern of the
# runs it fails ("MODE CONTEXT CALL INTERRUPTED"), one of how they fail (the
# first problem, "kind: reason") and what is wrong. A run that matches both
# is reported, not failed; any other failure (another way of failing
# included) fails the test. Each is an open defect (docs/DESIGN.md §10):
# fix it and remove its line.
KNOWN = [
    (r"^cpu nested/kill \S+ (timer_gettime|getitimer|timerfd_gettime|clock_mono|clock_thread|gettimeofday|clock)$",
     r"^wrong: gave up",
     "cpu mode: a thread whose sleep ends while another of its controller computes runs only once "
     "that one waits (natively they interleave): the killer thread's SIGUSR1 comes after the SIGALRM "
     "handler that reads clocks has returned (TCS_NO_FIFO=1 passes; cause not pinned down)"),
]


def known_defect(r, problems):
    label = "%s %s" % (r.mode, r.case.label())
    first = "%s: %s" % problems[0] if problems else ""
    return next((why for runs, how, why in KNOWN if re.search(runs, label) and re.search(how, first)), None)


def test_the_program_makes_the_corpus_calls():
    # cases.py's list of calls and their flags is the program's own
    wrong = run_corpus.check_program(run_corpus.Config())
    check(wrong is None, wrong or "")


def test_the_sample_covers_every_call_context_and_interrupted_call():
    sample = cases.sample(cases.SEED, cases.COUNT)
    for what, wanted, got in (
            ("call", list(cases.CALLS) + cases.PY_CALLS, {c.call for c in sample}),
            ("context", cases.CONTEXTS, {c.context for c in sample}),
            ("interrupted call", cases.INTERRUPTED + cases.PY_INTERRUPTED, {c.interrupted for c in sample})):
        missing = [w for w in wanted if w not in got]
        check(not missing, "the sample lacks the %s %s" % (what, ", ".join(missing)))
    check(sample == cases.sample(cases.SEED, cases.COUNT), "the same seed gives the same sample")


def test_the_sample_runs_natively_and_in_both_modes():
    sample = cases.sample(cases.SEED, cases.COUNT)
    t0 = time.monotonic()
    # A passing sample takes about a minute; one that hangs everywhere
    # (20 s a run) starts no run after BUDGET, so that the test still ends
    # inside meson's 300 s with the list of what failed.
    results = run_corpus.run_cases(sample, run_corpus.MODES, jobs=2, budget=BUDGET)
    passed, failed, kinds = run_corpus.tally(results)
    print("  %d cases, %d runs in %.1f s: %d passed, %d failed" %
          (len(sample), len(results), time.monotonic() - t0, passed, failed))
    known = [(r, p) for r, p in results if p and known_defect(r, p)]
    for r, p in known:
        print("  known defect: %s\n    (%s)" % (run_corpus.describe(r, p), known_defect(r, p)))
    failing = [run_corpus.describe(r, p) for r, p in results if p and not known_defect(r, p)]
    check(not failing, "%d of %d runs failed (%s), %d of them known defects:\n%s" % (
        failed, len(results), ", ".join("%s %d" % kv for kv in sorted(kinds.items())), len(known),
        "\n".join(failing)))


def test_cases_once_found_wrong_are_right_run_after_run():
    # Defects the corpus found that failed often alone: each case ten times
    # in lockstep, judged as the sample is. A handler run inside a device
    # read waiting for its record waited from the next record (1 run in 2).
    again = [cases.Case("nested/timer", "pause", "dev_fd")] * 10
    results = run_corpus.run_cases(again, ("lockstep",), jobs=1, budget=120)
    failing = [run_corpus.describe(r, p) for r, p in results if p]
    check(len(results) == 20 and not failing, "%d of %d runs failed:\n%s" % (
        len(failing), len(results), "\n".join(failing)))


if __name__ == "__main__":
    main(globals())
