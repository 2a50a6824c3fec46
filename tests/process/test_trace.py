"""Traces (docs/DESIGN.md §6): tcs-run --trace writes an MCAP file that the
official reader (@mcap/core, with Node.js) reads message by message, every
channel with a schema; after a SIGKILL midway everything but the last chunk
is still there."""

import json
import os
import signal
import struct
import time

from harness import (TCS_RUN, TCS_TRACE, assert_nothing_left, check, main, read_trace, run, session_processes,
                     start, tcs)

PD = os.path.join(os.environ.get("TCS_EXAMPLES", "."), "pendulum_pd")


def test_trace_of_a_pendulum_run():
    path = "/tmp/tcs-test-trace-%d.mcap" % os.getpid()
    try:
        r = tcs("-q", "-t", path, "--", PD, "--seconds", "2", timeout=60)
        check(r.returncode == 0, "the traced run succeeds", r)
        t = read_trace(path)
        print("  %d messages, %d bytes: %s" % (t["messages"], os.path.getsize(path), t["topics"]))
        check(t["channels"] == t["schemas"] == 6, "six topics, each with its schema", r)
        topics = t["topics"]
        check(topics["/tcs/controller"] == 1, "the controller described once")
        check(topics["/tcs/step"] == topics["/clock"] >= 2000, "a step and a clock message per step")
        # Each cycle of pendulum_pd is a clock_nanosleep and a torque line,
        # as many as the cycles it counts (its sensor reads are not traced:
        # docs/DESIGN.md §6).
        cycles = int(r.values()["cycles"])
        check(topics["/tcs/wait"] == cycles, "a wait per control cycle (%d)" % cycles, r)
        check(topics["/tcs/device"] == cycles, "a command per control cycle (%d)" % cycles, r)
        check(topics["/tcs/slice"] >= topics["/tcs/wait"], "slices")
    finally:
        if os.path.exists(path):
            os.unlink(path)


def chunks_begun(path):
    """The chunks an MCAP file as tcs writes it holds (mcap_writer.h: after
    its Header, each Chunk record followed by its Message Index records),
    the last perhaps cut short: [whole, messages] for each one begun, its
    messages counted from the index records found whole after it."""
    with open(path, "rb") as f:
        data = f.read()
    chunks, at = [], 8
    while at + 9 <= len(data):
        op, length = data[at], struct.unpack_from("<Q", data, at + 1)[0]
        whole = at + 9 + length <= len(data)
        if op == 0x06:
            chunks.append([whole, 0])
        elif op == 0x07 and whole and chunks:
            chunks[-1][1] += struct.unpack_from("<I", data, at + 11)[0] // 16
        elif op != 0x01:
            break
        at += 9 + length
    return chunks


def peak_rss_kb(args, timeout):
    """The most memory tcs-run (the coordinator in it) held in the run."""
    p = start(args)
    deadline = time.monotonic() + timeout
    while True:
        pid, status, usage = os.wait4(p.pid, os.WNOHANG)
        if pid:
            break
        if time.monotonic() > deadline:
            os.killpg(p.pid, signal.SIGKILL)
            os.wait4(p.pid, 0)
            raise AssertionError("%s: no end after %d s" % (args, timeout))
        time.sleep(0.05)
    p.returncode = os.waitstatus_to_exitcode(status)
    assert_nothing_left(p.pid)
    check(p.returncode == 0, "%s: exit 0" % args)
    return usage.ru_maxrss


def test_a_long_traced_run_holds_no_more_memory_than_a_short_one():
    # The trace is written as the run goes, not held until its end: the
    # writer once ran only where the coordinator and controller left a core
    # idle, on two cores never in a cpu-mode run, and 120 s of a 1 kHz
    # pendulum held 124 MB by its end.
    path = "/tmp/tcs-test-long-%d.mcap" % os.getpid()
    try:
        kb, written = {}, {}
        for seconds in (10, 60):
            kb[seconds] = peak_rss_kb([TCS_RUN, "-q", "-m", "cpu", "-d", "%ds" % seconds, "-t", path, "--", PD],
                                      timeout=120)
            written[seconds] = os.path.getsize(path) // 1024
        grown, more = kb[60] - kb[10], written[60] - written[10]
        print("  peak memory: %d kB for 10 s, %d kB for 60 s of a traced 1 kHz run, whose trace grew by %d kB"
              % (kb[10], kb[60], more))
        # A writer that held what it wrote (compressed or not) until the
        # end would grow by at least what the file grew; one that streams
        # holds a chunk and the index of chunks (tens of bytes each).
        check(more > 1024, "the last 50 s wrote more than a MiB of trace: %d kB" % more)
        check(grown < more // 2, "the last 50 s held less than half of what they wrote: %d of %d kB" % (grown, more))
    finally:
        if os.path.exists(path):
            os.unlink(path)


def test_trace_survives_sigkill():
    path = "/tmp/tcs-test-killed-%d.mcap" % os.getpid()
    try:
        p = start([TCS_RUN, "-q", "-m", "lockstep", "-t", path, "--", PD])
        # Killed once a second chunk has begun: the first is whole by then.
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline and (not os.path.exists(path) or len(chunks_begun(path)) < 2):
            time.sleep(0.05)
        os.kill(p.pid, signal.SIGKILL)
        p.communicate(timeout=10)
        # Reaped, tcs-run has sent its controller SIGKILL as it died
        # (PR_SET_PDEATHSIG: coordinator/spawn.cc); then they are gone as
        # soon as the kernel has torn them down.
        spared = [(pid, state, command) for pid, state, command in session_processes(p.pid) if not killed(pid, state)]
        assert_nothing_left(p.pid)
        check(not spared, "every controller sent SIGKILL as tcs-run died: not %s" % spared)
        t = read_trace(path, complete=False)
        chunks = chunks_begun(path)
        print("  killed after %d bytes, chunks begun [whole, messages indexed]: %s; %d messages readable" %
              (os.path.getsize(path), chunks, t["messages"]))
        # The writer writes each chunk whole, with its index, before the
        # next: every chunk but the last begun is whole, and all their
        # messages are read. The last one's are too if it is whole (its
        # index may be cut).
        check(len(chunks) >= 2, "killed after the first chunk: %s" % chunks)
        *before, (last_whole, last_indexed) = chunks
        kept = sum(n for _, n in before)
        check(t["truncated"] and all(whole for whole, _ in before) and kept > 0, "whole chunks before the last")
        check(t["messages"] >= kept + last_indexed if last_whole else t["messages"] == kept,
              "all but the last chunk is readable: %d messages, %d in the chunks before the last" %
              (t["messages"], kept))
        r = run([TCS_TRACE, "summary", "--json", path])
        check(r.returncode == 0, "tcs-trace summarises it", r)
        s = json.loads(r.stdout)
        # pendulum_pd's waits are its cycles' absolute sleeps: tcs-trace
        # reads as far as the official reader does.
        check(s["truncated"] and s["controllers"][0]["cycles"] == t["topics"]["/tcs/wait"],
              "as far as it goes: %d cycles" % s["controllers"][0]["cycles"], r)
    finally:
        if os.path.exists(path):
            os.unlink(path)


def killed(pid, state):
    """Whether process pid is dead, dying (PF_EXITING) or has SIGKILL
    pending (shared or its own)."""
    try:
        with open("/proc/%d/stat" % pid) as f:
            flags = int(f.read().rsplit(")", 1)[1].split()[6])
        with open("/proc/%d/status" % pid) as f:
            pending = [int(line.split()[1], 16) for line in f if line.startswith(("SigPnd:", "ShdPnd:"))]
    except (FileNotFoundError, ProcessLookupError):
        return True
    return state in "ZX" or flags & 0x4 or any(p & (1 << (signal.SIGKILL - 1)) for p in pending)


if __name__ == "__main__":
    main(globals())
