"""I2C buses (docs/DESIGN.md §9, [[i2c]]): /dev/i2c-1 with an MPU-6050 on
the pendulum's rod, driven by stock i2c-tools from Debian, unmodified
(i2cdetect, i2cget, i2cset, i2ctransfer), by a Python program through
i2c-dev's read and write, and by the IMU reader of examples/imu. Transfers
take their bits' time at the bus clock (exact in lockstep), and the chip
reads what the link feels."""

import json
import os
import tempfile

from harness import TCS_TRACE, check, main, need_tool, read_trace, scenario_file, tcs, trace_rows
from harness import run as run_tool

EXAMPLES = os.environ.get("TCS_EXAMPLES", "examples")

WORLD = """\
[sim]
step = "1ms"

[[model]]
name = "pendulum"
type = "pendulum"
initial_angle = %s

[[i2c]]
bus = 1
clock = "%s"

[[i2c.device]]
address = 0x68
chip = "mpu6050"
link = "pendulum.rod"
"""


def world(angle="0.0", clock="400kHz"):
    return scenario_file(WORLD % (angle, clock))


def need_i2c_tools():
    need_tool("i2cdetect", "i2c-tools")


def run(w, *argv, mode="lockstep"):
    r = tcs("-q", "-m", mode, "--epoch", "0", "-w", w, "--", *argv, timeout=60)
    check(r.returncode == 0, "%s runs" % argv[0], r)
    return r.stdout


def test_i2cdetect_finds_the_chip_and_nothing_else():
    need_i2c_tools()
    with world() as w:
        out = run(w, "i2cdetect", "-y", "1")
    found = [cell for line in out.splitlines()[1:] for cell in line.split()[1:] if cell != "--"]
    check(found == ["68"], "i2cdetect -y 1 sees one chip, at 0x68: %s" % found, out)


def test_i2cget_and_i2cset_read_and_write_registers():
    need_i2c_tools()
    with world() as w:
        check(run(w, "i2cget", "-y", "1", "0x68", "0x75").strip() == "0x68", "WHO_AM_I is 0x68")
        # PWR_MGMT_1 after reset: asleep (0x40); SMPLRT_DIV written, read back.
        check(run(w, "i2cget", "-y", "1", "0x68", "0x6b").strip() == "0x40", "asleep after reset")
        out = run(w, "sh", "-c", "i2cset -y 1 0x68 0x19 0x07 && i2cget -y 1 0x68 0x19")
        check(out.strip() == "0x07", "SMPLRT_DIV written and read back: %r" % out)
        r = tcs("-q", "-m", "lockstep", "-w", w, "--", "i2cget", "-y", "1", "0x69", "0x75", timeout=60)
        check(r.returncode != 0, "no chip at 0x69: i2cget fails", r)


def test_the_trace_holds_each_transfer_with_its_bits_time():
    """/tcs/wire/dev/i2c-1: each transfer, START to STOP, its messages as
    i2c-dev's (a read's data what was read), its result and who made it."""
    need_i2c_tools()
    with world() as w, tempfile.TemporaryDirectory() as tmp:
        trace = os.path.join(tmp, "i2c.mcap")
        r = tcs("-q", "-m", "lockstep", "-w", w, "-t", trace, "--", "sh", "-c",
                "i2cget -y 1 0x68 0x75; i2cget -y 1 0x50 0x00", timeout=60)
        check(r.returncode != 0 and "0x68" in r.stdout, "WHO_AM_I read, then nothing at 0x50", r)
        rows = trace_rows(trace, "/tcs/wire/dev/i2c-1")
        summary = json.loads(run_tool([TCS_TRACE, "summary", "--json", trace]).stdout)
        check(read_trace(trace)["topics"].get("/tcs/wire/dev/i2c-1") == len(rows), "Foxglove's readers decode them")
    check(len(rows) == 2 and all(x["from"] == "i2cget" for x in rows), "two transfers by i2cget", rows)
    who, none = rows
    # SMBus read byte data: START, 0x68 W, 0x75, repeated START, 0x68 R,
    # 0x68 NACKed, STOP: 1 + 9 + 9 + 1 + 9 + 9 + 1 bits at 400 kHz; an
    # address nobody ACKs: START, address, STOP.
    check(who["result"] == "0" and (who["messages[0].addr"], who["messages[0].flags"], who["messages[0].data[0]"]) ==
          ("104", "0", "117") and (who["messages[1].flags"], who["messages[1].data[0]"]) == ("1", "104"),
          "write 0x75 to 0x68, read 0x68 back", who)
    check(int(who["v_end_ns"]) - int(who["v_start_ns"]) == 39 * 2500, "39 bits at 400 kHz", who)
    check(none["result"] == "-6" and "no chip at 0x50" in none["note"] and
          int(none["v_end_ns"]) - int(none["v_start_ns"]) == 11 * 2500, "ENXIO after 11 bits, and why", none)
    wire = summary["wires"][0]
    check((wire["name"], wire["messages"], wire["bytes"], wire["busy_ns"], wire["refused"]) ==
          ("dev/i2c-1", 2, 4, 50 * 2500, 1), "summary --json: 2 transfers, 4 bytes, 50 bits, 1 failed: %s" % wire)
    print("  i2cget: 39 bits, 97.5 µs; no chip at 0x50: ENXIO after 11 bits, in the trace")


def test_i2ctransfer_reads_the_link_at_rest():
    need_i2c_tools()
    with world() as w:
        out = run(w, "sh", "-c", "i2cset -y 1 0x68 0x6b 0 && sleep 0.01 && i2ctransfer -y 1 w1@0x68 0x3b r14")
    b = [int(x, 16) for x in out.split()]
    check(len(b) == 14, "14 bytes read", out)
    word = lambda i: int.from_bytes(bytes(b[i:i + 2]), "big", signed=True)
    # Hanging at rest: +1 g along the rod's z (±2 g: 16384 LSB/g, g = 9.80665),
    # the world's 9.81 m/s²; nothing else.
    check(word(4) == round(9.81 / 9.80665 * 16384), "accel z %d LSB: 9.81 m/s² up" % word(4), out)
    check(word(0) == 0 and word(2) == 0, "accel x, y 0", out)
    check(all(word(i) == 0 for i in (8, 10, 12)), "gyro 0", out)


TIMING = """\
import fcntl, os, time
I2C_SLAVE = 0x0703
fd = os.open("/dev/i2c-1", os.O_RDWR)
fcntl.ioctl(fd, I2C_SLAVE, 0x68)
t0 = time.monotonic_ns(); os.write(fd, bytes([0x3b])); t1 = time.monotonic_ns()
os.read(fd, 14); t2 = time.monotonic_ns()
print(t1 - t0, t2 - t1)
"""


def test_a_transfer_takes_its_bits_time_at_the_bus_clock():
    for clock, hz in (("400kHz", 400000), ("100kHz", 100000)):
        with world(clock=clock) as w, scenario_file(TIMING) as prog:
            out = run(w, "python3", prog).split()
        write_ns, read_ns = int(out[0]), int(out[1])
        # START, address + ACK, one byte + ACK, STOP: 20 bits; a 14-byte
        # read: START, address, 14 bytes with their ACKs, STOP: 137 bits.
        # Exactly: the clock read after each transfer follows a wait for the
        # wire, so it is no spin's (docs/DESIGN.md §2) and costs nothing.
        bit = 1000000000 // hz
        check(write_ns == 20 * bit, "%s: a 1-byte write took %d ns, its 20 bits %d" % (clock, write_ns, 20 * bit))
        check(read_ns == 137 * bit, "%s: a 14-byte read took %d ns, its 137 bits %d" % (clock, read_ns, 137 * bit))
        print("  %s: write 1 byte %d ns (20 bits), read 14 bytes %d ns (137 bits)" % (clock, write_ns, read_ns))


def reader(w, mode, count):
    r = tcs("-q", "-m", mode, "-w", w, "--", os.path.join(EXAMPLES, "imu_reader"), "--count", str(count),
            timeout=60)
    check(r.returncode == 0, "imu_reader runs (%s)" % mode, r)
    return [line.split() for line in r.stdout.splitlines()]


def test_the_imu_reader_example_reads_gravity_and_the_swing():
    with world() as w:
        for mode in ("lockstep", "cpu"):
            rows = reader(w, mode, 5)
            check(len(rows) == 5, "5 samples (%s)" % mode, rows)
            for row in rows:
                ax, ay, az = (float(x) for x in row[2:5])
                # ±4 g: 8192 LSB/g, a quantum of 0.0012 m/s².
                check(abs(ax) < 0.002 and abs(ay) < 0.002 and abs(az - 9.81) < 0.002,
                      "at rest: (%g, %g, %g) m/s² is +g up (%s)" % (ax, ay, az, mode))
    with world(angle="0.5") as w:
        rows = reader(w, "lockstep", 20)
    gyro = [float(row[8]) for row in rows]
    # Released at 0.5 rad, the rod swings down: its rate grows, about the
    # hinge's axis alone.
    check(all(b > a for a, b in zip(gyro, gyro[1:])), "the rate grows as it swings down: %s" % gyro[:5])
    check(all(float(row[7]) == 0 and float(row[9]) == 0 for row in rows), "about one axis only")


def test_a_bad_chip_is_refused_at_its_line():
    text = (WORLD % ("0.0", "400kHz")).replace('"mpu6050"', '"bmi088"')
    line = text.splitlines().index('chip = "bmi088"') + 1
    with scenario_file(text) as w:
        r = tcs("-q", "-w", w, "--", "true", timeout=30)
    check(r.returncode == 2, "exit 2", r)
    check(r.stderr.count("\n") == 1 and ":%d: " % line in r.stderr and "bmi088" in r.stderr,
          "one line naming the file's line %d and the chip" % line, r)


if __name__ == "__main__":
    main(globals())
