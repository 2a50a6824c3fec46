"""A serial line's tty beyond reads and writes (docs/DESIGN.md §9, Serial):
TCSETS2 with BOTHER sets any rate, and the bytes then take 10 bits each at
it; tcflush drops the input that has arrived (TCIFLUSH, TCIOFLUSH), not
what is still on the wire, and TCOFLUSH no input; TIOCMGET reports the
modem lines as the program set them; every fd open on a line gets every
byte. The program is tests/programs/serial_line.py, in lockstep with
--no-slack, so each span is exact: bytes at 10 bits (8N1) at the rate,
floored to the ns as in test_serial.py, and the servo's Return Delay Time."""

import os

from harness import PYTHON, check, main, scenario_file, tcs

PROGRAM = os.path.join(os.environ.get("TCS_PROGRAMS_SRC", "."), "serial_line.py")
TTY = "/dev/ttyUSB0"
US = 1000
DELAY = 500 * US  # Return Delay Time at its factory value, 250 x 2 us (XM430 e-Manual)
PING, PING_REPLY = 10, 14  # Protocol 2.0: a PING, its status packet (3 bytes of data)

SCENARIO = """\
[[model]]
name = "pendulum"
type = "pendulum"
[[serial]]
path = "%s"
baud = 1000000
[[serial.servo]]
protocol = "dynamixel2"
id = 1
joint = "pendulum.hinge"
""" % TTY


def arrival(k, baud):
    """When byte k (from 0) of bytes sent back to back has arrived, from the
    first one's start: (k + 1) frames of 10 bits at baud, floored to the ns."""
    return (k + 1) * 10 * 10**9 // baud


def probe(case, *args):
    with scenario_file(SCENARIO) as world:
        r = tcs("-q", "-m", "lockstep", "--no-slack", "-w", world, "--", PYTHON, PROGRAM, case, TTY, *args,
                timeout=60)
    check(r.returncode == 0, "serial_line %s runs" % case, r)
    return r.values(), r


def is_ping_status(hexed):
    """A PING's status packet from id 1 without error: header, id 1, length
    7, instruction 0x55, error 0 (the rest is the model and firmware and
    the CRC)."""
    return len(hexed) == 2 * PING_REPLY and hexed.startswith("fffffd000107005500")


def test_tcsets2_with_bother_sets_any_rate_and_the_bytes_follow_it():
    v, r = probe("bother")
    check(v["at_57600"] == "0", "at 57600 the servo (at 1 Mbit/s) does not answer", r)
    check(v["cbaud"] == "0o10000" and v["ispeed"] == v["ospeed"] == "1000000",
          "TCGETS2: BOTHER and 1000000 both ways", r)
    ping = arrival(PING - 1, 1000000) + DELAY + arrival(PING_REPLY - 1, 1000000)
    check(int(v["ping_ns"]) == ping and is_ping_status(v["ping_reply"]),
          "at 1 Mbit/s set by BOTHER the servo answers: PING %s ns, expected %d" % (v["ping_ns"], ping), r)
    for rate in (1000000, 250000, 1234567):
        want = arrival(99, rate)
        check(int(v["drain_%d_ns" % rate]) == want,
              "100 bytes at %d: tcdrain after %s ns, expected %d" % (rate, v["drain_%d_ns" % rate], want), r)
        if rate != 1000000:
            check(v["ospeed_%d" % rate] == str(rate), "TCGETS2 reads %d back" % rate, r)
    print("  PING at 1 Mbit/s (BOTHER) %d ns; 100 bytes drained in %s, %s, %s ns at 1 M, 250 k, 1234567" %
          (ping, v["drain_1000000_ns"], v["drain_250000_ns"], v["drain_1234567_ns"]))


def test_tcflush_drops_the_input_that_has_arrived():
    # Byte 7 of the reply arrives 675 us after the PING is written: its
    # 10 bytes, the delay, 7 bytes at 10 us (and 5 us into the 8th).
    mid = arrival(PING - 1, 1000000) + DELAY + arrival(6, 1000000) + 5 * US
    v, r = probe("flush", str(mid))
    reply = v["TCOFLUSH_read"]
    check(v["TCOFLUSH_before"] == v["TCOFLUSH_after"] == "14" and is_ping_status(reply),
          "TCOFLUSH leaves the input: 14 bytes before and after, then read", r)
    for queue in ("TCIFLUSH", "TCIOFLUSH"):
        check(v[queue + "_before"] == "14" and v[queue + "_after"] == "0" and v[queue + "_read"] == "-",
              "%s drops the 14 bytes that had arrived" % queue, r)
    check(v["mid_read"] == reply[14:],
          "in the middle: the 7 bytes arrived go, the 7 on the wire come (%s of %s)" % (v["mid_read"], reply), r)
    check(v["bad_queue"] == "EINVAL", "a queue that is none of the three: EINVAL", r)


def test_tiocmget_reports_the_modem_lines_as_set():
    """The tty layer raises DTR and RTS when a line with a rate is opened
    (tty_port_block_til_ready), and TIOCMBIC and TIOCMBIS lower and raise
    them; TIOCMGET reports them so (pyserial's dtr and rts, an RS-485
    adapter's direction line)."""
    v, r = probe("modem")
    dtr_rts = 0x002 | 0x004  # TIOCM_DTR, TIOCM_RTS
    check(v["opened"] == str(dtr_rts), "DTR and RTS up after open: %s" % v["opened"], r)
    check(v["cleared"] == "0", "both down after TIOCMBIC: %s" % v["cleared"], r)
    check(v["rts"] == str(0x004), "RTS alone up after TIOCMBIS(RTS): %s" % v["rts"], r)


def test_every_fd_open_on_a_line_gets_every_byte():
    v, r = probe("twofds")
    ping = arrival(PING - 1, 1000000) + DELAY + arrival(PING_REPLY - 1, 1000000)
    check(is_ping_status(v["a"]) and v["b"] == v["a"], "both fds read the whole reply: %s, %s" % (v["a"], v["b"]), r)
    check(v["a_ns"] == v["b_ns"] == str(ping), "each has it when its last byte has arrived (%d ns)" % ping, r)
    check(v["a_left"] == v["b_left"] == "0", "and nothing more", r)


if __name__ == "__main__":
    main(globals())
