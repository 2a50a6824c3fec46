"""A serial line with a Dynamixel servo on it (docs/DESIGN.md §9, [[serial]]
and [[serial.servo]]): a controller opens the tty, sets it with termios and
talks Protocol 2.0 to an XM430-W350 model driving the pendulum's hinge.
Every byte takes its 10 bit times (8N1) at the baud each way, and the servo
answers after its Return Delay Time, so a transaction's virtual time is
exact in lockstep and late in cpu mode by no more than what the controller
computed meanwhile. The programs are tests/programs/dxl_probe.py (with
dxl_bus.py: packets of their own over os and termios, no SDK)."""

import math
import os
import re
import tempfile

from harness import AHEAD, PYTHON, check, main, read_trace, scenario_file, tcs, trace_rows

PROBE = os.path.join(os.environ.get("TCS_PROGRAMS_SRC", "."), "dxl_probe.py")
TTY = "/dev/ttyUSB0"
MS = 1000000
US = 1000
DELAY = 500 * US  # Return Delay Time at its factory value, 250 x 2 us
# Packet sizes (Protocol 2.0): PING 10, its status 14; READ 14, a status
# with 4 bytes of data 15.
PING, PING_REPLY, READ, READ_REPLY = 10, 14, 14, 15

# The pendulum (1 kg, 1 m) at 0.3 rad unless `model` says otherwise.
SCENARIO = """\
[[model]]
name = "pendulum"
type = "pendulum"
{model}[[serial]]
path = "{tty}"
baud = {baud}
[[serial.servo]]
protocol = "dynamixel2"
id = 1
joint = "pendulum.hinge"
{extra}"""


def arrival(k, baud):
    """When byte k (from 0) of bytes sent back to back has arrived, from
    the first one's start: (k + 1) frames of 10 bits, floored to the ns."""
    return (k + 1) * 10 * 10**9 // baud


def transaction(out, back, baud, delay=DELAY):
    """From writing an out-byte packet to the last of a back-byte reply."""
    return arrival(out - 1, baud) + delay + arrival(back - 1, baud)


SWINGING = "initial_angle = 0.3\n"


def probe(mode, baud, case, *args, options=(), model=SWINGING, extra=""):
    with scenario_file(SCENARIO.format(model=model, tty=TTY, baud=baud, extra=extra)) as world:
        r = tcs("-q", "-m", mode, *options, "-w", world, "--", PYTHON, PROBE, case, TTY, baud, *args, timeout=120)
    check(r.returncode == 0, "%s: dxl_probe %s runs" % (mode, case), r)
    return r.values(), r


def on_time(v, name, exact, mode, r, byte=None):
    """A span (name_ns) exactly `exact` in lockstep. In cpu mode late by no
    more than the CPU the program spent in it (name_cpu, read around it),
    and if `byte` is given no more than that (one byte's time); and either
    way give or take what a clock read may run ahead of the CPU the kernel
    charged (AHEAD): the span's ends are the program's clock reads, what
    the line did in between is stamped with the kernel's CPU."""
    got = int(v[name + "_ns"])
    lo, hi = exact, exact
    if mode != "lockstep":
        lo, hi = exact - AHEAD, exact + int(v[name + "_cpu"]) + AHEAD
        if byte is not None:
            hi = min(hi, exact + byte)
    check(lo <= got <= hi, "%s: %s %.6f ms, expected %.6f ms%s" %
          (mode, name, got / MS, exact / MS, "" if mode == "lockstep" else " (%.6f to %.6f)" % (lo / MS, hi / MS)), r)
    return got


def test_a_read_round_trip_is_its_bytes_and_the_return_delay():
    baud = 57600
    byte = arrival(0, baud)
    ping, read = transaction(PING, PING_REPLY, baud), transaction(READ, READ_REPLY, baud)
    for mode in ("lockstep", "cpu"):
        v, r = probe(mode, baud, "roundtrip")
        got_ping = on_time(v, "ping", ping, mode, r, byte)
        got_read = on_time(v, "read", read, mode, r, byte)
        check(v["ping_reply"].startswith("fffffd00010700550") and v["read_error"] == "0",
              "%s: the status packets: PING's from id 1, READ without error" % mode, r)
        # The pendulum hangs at 0.3 rad: 2048 + 0.3 * 4096 / 2pi counts,
        # or a little less as it starts to swing down.
        check(2048 < int(v["position"]) <= 2048 + round(0.3 * 4096 / (2 * math.pi)),
              "%s: Present Position is the hinge's angle (%s)" % (mode, v["position"]), r)
        print("  %-8s 57600 baud: PING %.6f ms (exactly %.6f), READ %.6f ms (%.6f)" %
              (mode, got_ping / MS, ping / MS, got_read / MS, read / MS))


def test_the_trace_holds_the_line_s_bytes_with_their_times():
    """/tcs/wire/dev/ttyUSB0: each write's bytes and each reply, from the
    first start bit to the last stop bit, and who sent them; what the
    servo refused, noted."""
    baud = 57600
    with tempfile.TemporaryDirectory() as tmp:
        trace = os.path.join(tmp, "serial.mcap")
        probe("lockstep", baud, "faults", options=("-t", trace))
        rows = trace_rows(trace, "/tcs/wire/dev/ttyUSB0")
        check(read_trace(trace)["topics"].get("/tcs/wire/dev/ttyUSB0") == len(rows), "Foxglove's readers decode them")
    sent = [x for x in rows if x["from"] != "servos"]
    first, reply = sent[0], sent[1]
    count = lambda x: len([k for k in x if k.startswith("data[") and x[k] != ""])
    check(first["from"] == PYTHON and reply["from"] == "servo 1", "the probe's packet, then servo 1's", rows[:2])
    n, m = count(first), count(reply)
    check(int(first["v_end_ns"]) - int(first["v_start_ns"]) == arrival(n - 1, baud) and
          int(reply["v_start_ns"]) - int(first["v_end_ns"]) == DELAY and
          int(reply["v_end_ns"]) - int(reply["v_start_ns"]) == arrival(m - 1, baud),
          "%d bytes at 57600 baud, the Return Delay Time, %d bytes back" % (n, m), rows[:2])
    notes = [x["note"] for x in rows if x["from"] == "servos"]
    check(any("CRC does not match" in n for n in notes), "the bad CRC noted: %s" % notes)
    print("  %d bytes out in %.6f ms, 500 µs, %d back in %.6f ms; %d notes" %
          (n, arrival(n - 1, baud) / MS, m, arrival(m - 1, baud) / MS, len(notes)))


def test_at_1_mbit_and_with_the_return_delay_written():
    baud = 1000000
    for mode in ("lockstep", "cpu"):
        seen = []
        # Return Delay Time (9) in units of 2 us: the factory 250, then 0
        # and 10 written (torque is off: the EEPROM area may be written).
        for units in (None, 0, 10):
            delay = DELAY if units is None else units * 2 * US
            v, r = probe(mode, baud, "roundtrip", *([] if units is None else [units]))
            if units is not None:
                check(v["delay_write_error"] == "0", "%s: WRITE of Return Delay Time %d accepted" % (mode, units), r)
            on_time(v, "ping", transaction(PING, PING_REPLY, baud, delay), mode, r)
            seen.append(on_time(v, "read", transaction(READ, READ_REPLY, baud, delay), mode, r))
        print("  %-8s 1 Mbit/s READ: %.6f ms at the factory delay, %.6f ms with 0, %.6f ms with 20 us" %
              ((mode,) + tuple(s / MS for s in seen)))


def test_vmin_vtime_and_nonblocking_reads():
    baud = 57600
    for mode in ("lockstep", "cpu"):
        # No spin costs and no timer slack: the reads' own times alone.
        v, r = probe(mode, baud, "vtime", options=("--spin-cost", "0", "--no-slack"))
        check(v["vmin0_vtime0_result"] == "0", "%s: VMIN 0, VTIME 0 with nothing come: b''" % mode, r)
        on_time(v, "vmin0_vtime0", 0, mode, r)
        check(v["nonblock_result"] == "EAGAIN", "%s: O_NONBLOCK with nothing come: EAGAIN" % mode, r)
        on_time(v, "nonblock", 0, mode, r)
        check(v["vtime2_silent_result"] == "0", "%s: VMIN 0, VTIME 2, no answer: b''" % mode, r)
        on_time(v, "vtime2_silent", 200 * MS, mode, r)
        # VTIME ends at the first byte: a READ's reply's first byte.
        first = int(v["vtime2_first_result"])
        check(first == 1 if mode == "lockstep" else first >= 1, "%s: VTIME's read returns its first byte" % mode, r)
        on_time(v, "vtime2_first", arrival(READ - 1, baud) + DELAY + arrival(0, baud), mode, r)
        n = int(v["vmin5_result"])
        check(n == 5 if mode == "lockstep" else 5 <= n <= READ_REPLY, "%s: VMIN 5 returns 5 bytes (%d)" % (mode, n), r)
        on_time(v, "vmin5", arrival(READ - 1, baud) + DELAY + arrival(4, baud), mode, r)
        on_time(v, "vmin_rest", transaction(READ, READ_REPLY, baud), mode, r)
        check(v["vtime2_first_whole"] == v["vmin_whole"] == "1", "%s: the replies read whole" % mode, r)
    print("  VMIN 0/VTIME 0: b'' at once; O_NONBLOCK: EAGAIN; VTIME 2: b'' at 200 ms, or the first byte; "
          "VMIN 5: 5 bytes at the 5th's arrival")


def test_a_spin_on_a_nonblocking_read_gets_the_reply_on_time():
    # The SDK's way: read() on an O_NONBLOCK tty again and again, a
    # CLOCK_REALTIME timeout checked each time. In lockstep each empty read
    # and clock read costs a spin's (docs/DESIGN.md §2: --epoch's 500 and
    # 25 ns, or --spin-cost's), a turn of the loop both. The span starts
    # at a clock read after a sleep (free); the write goes then; the loop's
    # first clock read costs one.
    # - The reply's last byte is read by the first read after it came: a
    #   turn after the last empty one at most. That read got bytes, so the
    #   clock read after it is free; the span's closing one costs one.
    # - No reply: the loop turns until its clock has gone past 50 ms, the
    #   first turn that does, exactly; and the closing read costs one.
    baud = 57600
    exact = transaction(READ, READ_REPLY, baud)
    for options, read, clock in ((("--epoch", "0"), 500, 25), (("--spin-cost", "40ns,3us"), 3000, 40)):
        v, r = probe("lockstep", baud, "spin", options=options)
        got, silent, turn = int(v["reply_ns"]), int(v["silent_ns"]), read + clock
        check(v["reply_len"] == "15" and exact <= got <= exact + turn + clock and int(v["reply_tries"]) > 0,
              "lockstep %s: the reply after %.6f ms, expected %.6f ms + at most %d ns" %
              (options, got / MS, exact / MS, turn + clock), r)
        turns = 50 * MS // turn + 1
        check(v["silent_len"] == "0" and int(v["silent_tries"]) == turns and silent == clock + turns * turn + clock,
              "lockstep %s: an unanswered PING's timeout after %s turns of %d ns, at %d ns (%d)" %
              (options, v["silent_tries"], turn, clock + turns * turn + clock, silent), r)
        print("  lockstep %s: reply %.6f ms after the write (%.6f exactly), %s empty reads; timeout %.6f ms" %
              (" ".join(options), got / MS, exact / MS, v["reply_tries"], silent / MS))
    # In cpu mode the spin's CPU is its time: it sees the reply within a
    # turn of its loop, well within a byte's time.
    v, r = probe("cpu", baud, "spin")
    got = int(v["reply_ns"])
    check(v["reply_len"] == "15" and exact - AHEAD <= got <= exact + arrival(0, baud),
          "cpu: the reply after %.6f ms, expected %.6f ms" % (got / MS, exact / MS), r)
    print("  cpu:      reply %.6f ms after the write, %s empty reads" % (got / MS, v["reply_tries"]))


def test_tcdrain_and_fionread():
    baud = 57600
    for mode in ("lockstep", "cpu"):
        v, r = probe(mode, baud, "drain")
        # tcdrain returns when the last of the READ's 14 bytes has left.
        on_time(v, "drain", arrival(READ - 1, baud), mode, r)
        check(v["after_drain"] == "0", "%s: nothing arrived yet at tcdrain's return" % mode, r)

        def arrived(t):
            """Bytes of the reply arrived by t (from the write)."""
            start = arrival(READ - 1, baud) + DELAY
            return sum(1 for k in range(READ_REPLY) if start + arrival(k, baud) <= t)
        # The clock reads around each FIONREAD: in cpu mode each may run
        # ahead of the time its ioctl is stamped with (on_time); and the
        # write itself is later than the read before it by the CPU between
        # them, as much as tcdrain's return is late (a preemption there).
        ahead = AHEAD if mode == "cpu" else 0
        late = max(0, int(v["drain_ns"]) - arrival(READ - 1, baud)) if mode == "cpu" else 0
        counts = []
        for i in range(12):
            n, t0, t1 = (int(v["sample%d_%s" % (i, k)]) for k in ("count", "from", "to"))
            lo, hi = arrived(t0 - ahead - late), arrived(t1 + ahead)
            check(lo <= n <= hi, "%s: FIONREAD %d between %.6f and %.6f ms: %d to %d bytes" %
                  (mode, n, t0 / MS, t1 / MS, lo, hi), r)
            counts.append(n)
        check(len(set(counts)) >= 5, "%s: FIONREAD counts the reply coming in: %s" % (mode, counts), r)
        check(v["read_len"] == "15" and v["after_read"] == "0", "%s: then read whole, nothing left" % mode, r)
        print("  %-8s tcdrain %.6f ms (14 bytes); FIONREAD every 0.2 ms: %s" %
              (mode, int(v["drain_ns"]) / MS, counts))


def test_a_bad_crc_is_answered_and_an_unknown_id_or_baud_is_not():
    for mode in ("lockstep", "cpu"):
        v, r = probe(mode, 57600, "faults")
        check(v["bad_crc_error"] == "3" and v["bad_crc_id"] == "1",
              "%s: a READ with a bad CRC gets a status with the CRC Error (3)" % mode, r)
        check("dropped a packet to id 1 (instruction 2): its CRC does not match" in r.stderr,
              "%s: and the log says so" % mode, r)
        check(v["unknown_id_len"] == "0", "%s: a PING to id 7, which no servo has, gets no reply" % mode, r)
        check(v["other_baud_len"] == "0", "%s: a PING with the tty at 115200 gets none" % mode, r)
        check(v["back_len"] == "14" and v["back_error"] == "0", "%s: back at 57600 the servo answers" % mode, r)
    print("  bad CRC: status error 3; id 7: silence; tty at 115200: silence; back at 57600: PING answered")


# A lighter rod than the default (0.5 kg, 0.5 m: its weight's torque at
# most 1.23 N*m) hanging at rest, and the angle read beside the servo.
LIGHT = "length = 0.5\nmass = 0.5\n"
ANGLE = '[[device]]\npath = "/dev/tcs/angle"\nkind = "sensor"\nsignals = ["pendulum.hinge.position"]\n' \
        'mode = "latest"\n'
COUNTS = 4096 / (2 * math.pi)


def test_position_control_moves_the_simulated_joint():
    # Torque on in Position Control Mode (the factory's), Goal Position
    # 0.8 rad up from hanging: the servo's own loop drives the hinge there.
    goal = 2048 + round(0.8 * COUNTS)
    # Its P-only loop (Position P Gain 800: 800/128 PWM units a count, 885
    # the full 12 V over 12/2.3 ohm, 4.1/2.3 N*m/A) holds the rod's weight
    # a few counts short of the goal: where the two torques meet.
    stiffness = 800 / 128 / 885 * 12 / (12 / 2.3) * (4.1 / 2.3)  # N*m a count

    def weight(counts):
        return 0.5 * 9.81 * 0.25 * math.sin((counts - 2048) / COUNTS)
    sag = min(range(100), key=lambda s: abs(stiffness * s - weight(goal - s)))
    for mode in ("lockstep", "cpu"):
        v, r = probe(mode, 1000000, "move", goal, "/dev/tcs/angle", model=LIGHT, extra=ANGLE)
        start, held, angle = int(v["start"]), int(v["held"]), float(v["angle"])
        check(start == 2048, "%s: hanging at rest, Present Position 2048 (%d)" % (mode, start), r)
        check(int(v["reached_ns"]) < 1000 * MS,
              "%s: within 40 counts of the goal within 1 s (%s ns)" % (mode, v["reached_ns"]), r)
        check(abs(goal - sag - held) <= 2, "%s: held at %d, %d short of the goal %d where the weight is held (%d)" %
              (mode, held, goal - held, goal, sag), r)
        check(abs(angle * COUNTS + 2048 - held) <= 1, "%s: the hinge is there: %.4f rad" % (mode, angle), r)
        print("  %-8s goal %d: near it after %.1f ms, held at %d (the weight: %d short), hinge at %.4f rad" %
              (mode, goal, int(v["reached_ns"]) / MS, held, sag, angle))


SECOND = '[[serial.servo]]\nprotocol = "dynamixel2"\nid = {id}\njoint = "{joint}"\n'
BAD = [
    # (what, baud, the first servo's protocol, a second servo, the line at
    # fault, what the error says). [[serial]] is at line 5 (baud at 7), the first
    # servo's table at 8 to 11, a second's at 12 to 15.
    ("an unknown protocol", 57600, "dynamixel1", "", 9, "unknown protocol 'dynamixel1'"),
    ("a duplicate id", 57600, "dynamixel2", SECOND.format(id=1, joint="pendulum.hinge"), 14,
     "servo id 1 is already used"),
    ("a joint that does not exist", 57600, "dynamixel2", SECOND.format(id=2, joint="pendulum.knee"), 15,
     "unknown joint 'pendulum.knee'"),
    ("a model that does not exist", 57600, "dynamixel2", SECOND.format(id=2, joint="arm.hinge"), 15,
     "no model 'arm'"),
    # (The servo's rates are checked where the line is made: at [[serial]].)
    ("a baud no Dynamixel X takes", 38400, "dynamixel2", "", 7, "baud 38400 is not a rate of a Dynamixel X servo"),
]


def test_a_bad_serial_scenario_is_refused_at_its_line():
    for what, baud, protocol, second, line, says in BAD:
        text = SCENARIO.format(model=SWINGING, tty=TTY, baud=baud, extra=second)
        text = text.replace('"dynamixel2"', '"%s"' % protocol, 1)
        with scenario_file(text) as world:
            r = tcs("-q", "-w", world, "--", "true", timeout=30)
        lines = r.stderr.strip().splitlines()
        check(r.returncode == 2 and len(lines) == 1 and
              re.match(r"tcs-run: %s:%d: .*%s" % (re.escape(world), line, re.escape(says)), lines[0]),
              "%s: exit 2 and one line '%s:%d: ...%s...'" % (what, world, line, says), r)
        print("  %-28s %s" % (what + ":", lines[0].split(": ", 2)[2]))


if __name__ == "__main__":
    main(globals())
