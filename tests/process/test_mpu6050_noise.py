"""An MPU-6050's noise (docs/DESIGN.md §9, I2C; [[i2c.device]] accel_noise
and gyro_noise): Gaussian, of the standard deviations the scenario gives,
drawn per sample from a stream of the run's --seed, so one seed repeats
every reading, another changes them, and a sample read twice reads the
same. The chip hangs at rest on the pendulum's rod, so what it should read
is known without tcs: +9.81 m/s² along z (the world's gravity, the specific
force of a body at rest), nothing else; the rest is noise. The program reads
the 14 data registers through i2c-dev at times it sleeps to (lockstep,
--no-slack), half a millisecond after each step's boundary."""

import math

from harness import check, main, scenario_file, tcs

ACCEL_NOISE = 0.5   # m/s²: 835 LSB at ±2 g
GYRO_NOISE = 0.05   # rad/s: 375 LSB at ±250 °/s
GRAVITY = 9.81      # the world's (the pendulum model's g)
STANDARD_G = 9.80665  # the chip's LSB per g is per standard g
LSB_PER_G = 16384     # ±2 g, the power-on range
LSB_PER_DPS = 131     # ±250 °/s

WORLD = """\
[sim]
step = "1ms"

[[model]]
name = "pendulum"
type = "pendulum"
initial_angle = 0.0

[[i2c]]
bus = 1

[[i2c.device]]
address = 0x68
chip = "mpu6050"
link = "pendulum.rod"
accel_noise = %r
gyro_noise = %r
""" % (ACCEL_NOISE, GYRO_NOISE)

READER = """\
import ctypes, fcntl, os, struct, sys, time
libc = ctypes.CDLL(None)
class timespec(ctypes.Structure):
    _fields_ = [("s", ctypes.c_long), ("ns", ctypes.c_long)]
def sleep_until(t):
    libc.clock_nanosleep(time.CLOCK_MONOTONIC, 1, ctypes.byref(timespec(t // 10**9, t % 10**9)), None)
fd = os.open("/dev/i2c-1", os.O_RDWR)
fcntl.ioctl(fd, 0x0703, 0x68)              # I2C_SLAVE
os.write(fd, bytes([0x6B, 0]))             # PWR_MGMT_1: awake
os.write(fd, bytes([0x1A, 1]))             # CONFIG: DLPF 1, a 1 kHz gyro rate
os.write(fd, bytes([0x19, int(sys.argv[1])]))  # SMPLRT_DIV: 1 kHz / (1 + div)
t0 = (time.monotonic_ns() // 10**6 + 10) * 10**6
rows = []
for k in range(int(sys.argv[2])):
    sleep_until(t0 + k * 10**6 + 500000)   # mid-step, after the step's sample
    os.write(fd, bytes([0x3B]))            # ACCEL_XOUT_H: accel, temperature, gyro
    rows.append(" ".join(map(str, struct.unpack(">7h", os.read(fd, 14)))))
print("\\n".join(rows))
"""


def readings(seed, div=0, n=600):
    """n readings (accel x y z, temperature, gyro x y z, in LSB), one a ms."""
    with scenario_file(WORLD) as world, scenario_file(READER) as prog:
        r = tcs("-q", "-m", "lockstep", "--no-slack", "--epoch", "0", "--seed", str(seed), "-w", world, "--",
                "python3", prog, str(div), str(n), timeout=120)
    check(r.returncode == 0, "the reader runs", r)
    rows = [tuple(int(x) for x in line.split()) for line in r.stdout.splitlines()]
    check(len(rows) == n, "%d readings" % n, r)
    return rows, r


def noise_of(rows):
    """The readings less what the chip at rest reads, in m/s² and rad/s."""
    accel, gyro = [], []
    for row in rows:
        truth = (0.0, 0.0, GRAVITY)
        accel += [row[i] / LSB_PER_G * STANDARD_G - truth[i] for i in range(3)]
        gyro += [row[4 + i] / LSB_PER_DPS * math.pi / 180 for i in range(3)]
    return accel, gyro


def test_the_noise_has_the_configured_deviation_and_no_bias():
    rows, r = readings(7)
    for what, draws, sigma in (("accel", noise_of(rows)[0], ACCEL_NOISE), ("gyro", noise_of(rows)[1], GYRO_NOISE)):
        n = len(draws)
        mean = sum(draws) / n
        sd = math.sqrt(sum((x - mean) ** 2 for x in draws) / (n - 1))
        # Five standard errors each (a Gaussian exceeds that once in 1.7
        # million): the mean's is sigma/sqrt(n), the sample deviation's
        # sigma/sqrt(2(n-1)). Rounding to the LSB (0.0006 m/s², 0.00013
        # rad/s) moves neither by a thousandth of its bound.
        check(abs(mean) <= 5 * sigma / math.sqrt(n), "%s: mean %.5f of %d draws, sigma %g" % (what, mean, n, sigma), r)
        check(abs(sd / sigma - 1) <= 5 / math.sqrt(2 * (n - 1)),
              "%s: deviation %.5f of %d draws, configured %g" % (what, sd, n, sigma), r)
        print("  %s: %d draws, mean %+.5f, deviation %.5f (configured %g)" % (what, n, mean, sd, sigma))


def test_the_seed_fixes_every_reading_and_each_sample_draws_anew():
    a, _ = readings(7, n=200)
    again, _ = readings(7, n=200)
    other, _ = readings(8, n=200)
    check(a == again, "the same seed: the same 200 readings")
    check(all(x != y for x, y in zip(a, other)), "another seed: every reading different")
    # At 1 kHz every read is a new sample: no two in a row the same (a draw
    # per run would make them all so).
    check(all(x != y for x, y in zip(a, a[1:])), "each sample of its own")


def test_a_sample_read_ten_times_reads_the_same():
    """At 100 Hz (SMPLRT_DIV 9) and a read a millisecond, each sample is read
    ten times: the noise is drawn per sample, not per read."""
    rows, r = readings(7, div=9, n=200)
    runs = [1]
    for x, y in zip(rows, rows[1:]):
        if x == y:
            runs[-1] += 1
        else:
            runs.append(1)
    check(len(runs) >= 19 and all(n == 10 for n in runs[1:-1]) and runs[0] <= 10 and runs[-1] <= 10,
          "runs of 10 equal readings: %s" % runs, r)


if __name__ == "__main__":
    main(globals())
