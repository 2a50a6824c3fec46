"""Sensor models (docs/DESIGN.md §8, [[sensor]]): what a device's reader sees
of a signal is its value `latency` ago plus bias and Gaussian noise,
quantised, sampled at the sensor's rate. Read here by a stock program
(head) from a 1 kHz stream in lockstep: the noise has the declared standard
deviation, lies on the declared grid, repeats with --seed and differs with
another seed."""

import math
import os
import statistics
import tempfile

from harness import check, main, scenario_file, tcs

# A pendulum hanging at rest: its angle is exactly 0, so what the sensor
# reads is its model alone.
WORLD = """\
[sim]
step = "1ms"
model = "pendulum"

[[device]]
path = "/dev/tcs/pendulum/state"
kind = "sensor"
signals = ["pendulum.hinge.position", "pendulum.hinge.velocity"]
rate = "1kHz"

[[sensor]]
signal = "pendulum.hinge.position"
noise = 0.01
bias = 0.05
resolution = 0.002

[[sensor]]
signal = "pendulum.hinge.velocity"
latency = "2ms"
rate = "250Hz"
"""

N = 3000


def read(world, *options):
    r = tcs("-q", "-m", "lockstep", "--epoch", "0", *options, "-w", world, "--",
            "head", "-n", str(N), "/dev/tcs/pendulum/state", timeout=60)
    check(r.returncode == 0, "head reads the sensor", r)
    rows = [[float(x) for x in line.split()] for line in r.stdout.splitlines()]
    check(len(rows) == N and all(len(row) == 2 for row in rows), "head printed %d records of two values" % N, r)
    return r.stdout, rows


def test_a_noisy_quantised_sensor_has_its_deviation_and_grid_and_repeats_with_its_seed():
    with scenario_file(WORLD) as world:
        out, rows = read(world, "--seed", "5")
        again, _ = read(world, "--seed", "5")
        other, other_rows = read(world, "--seed", "6")
    angles = [row[0] for row in rows]
    mean, sd = statistics.fmean(angles), statistics.pstdev(angles)
    # 3000 draws: the deviation's relative standard error is
    # 1 / sqrt(2 (N - 1)) = 1.3 % (normal draws), the mean's 0.01 / sqrt(N)
    # = 0.00018 rad; quantising to 0.002 adds 0.002^2/12 to the variance.
    # Both within 5 standard errors (by chance outside once in 1.7 million).
    expected_sd = math.sqrt(0.01 ** 2 + 0.002 ** 2 / 12)
    sd_error = 1 / math.sqrt(2 * (N - 1))
    check(abs(sd / expected_sd - 1) < 5 * sd_error, "standard deviation %.5f rad, declared 0.01 (%.5f quantised)" %
          (sd, expected_sd))
    check(abs(mean - 0.05) < 5 * 0.01 / math.sqrt(N), "mean %.5f rad: the bias, 0.05" % mean)
    check(all(abs(a / 0.002 - round(a / 0.002)) < 1e-6 for a in angles), "every angle on the 0.002 rad grid")
    check(len(set(angles)) > 20, "and noisy: %d distinct values" % len(set(angles)))
    check(out == again, "the same seed gives the same %d records, byte for byte" % N)
    check(sum(a != b for a, b in zip(angles, (row[0] for row in other_rows))) > N // 2,
          "another seed, other values")
    # The velocity's model has no noise: the truth, held at 250 Hz (4
    # records a sample), 2 ms late: exactly 0 at rest.
    check(all(row[1] == 0 for row in rows), "the noiseless velocity reads its truth, 0")
    print("  3000 angles: mean %.5f (bias 0.05), sd %.5f (declared 0.01), on a 0.002 grid; --seed repeats" %
          (mean, sd))


SWING = """\
[sim]
step = "1ms"
model = "pendulum"
[model]
initial_angle = 0.5

[[device]]
path = "/dev/tcs/s"
kind = "sensor"
signals = ["pendulum.hinge.position", "pendulum.hinge.velocity"]
rate = "1kHz"
"""


def swing(models=""):
    with scenario_file(SWING + models) as w:
        r = tcs("-q", "-m", "lockstep", "-w", w, "--", "head", "-n", "400", "/dev/tcs/s", timeout=60)
    check(r.returncode == 0, "head reads the sensor", r)
    return [[float(x) for x in line.split()] for line in r.stdout.splitlines()]


def test_a_rate_holds_samples_and_latency_delays():
    # A swinging pendulum read at 1 kHz, without sensor models and with:
    # the velocity sampled at 250 Hz (each sample held for 4 records) and
    # the angle 2 ms late (two records behind). Lockstep: the same world.
    truth = swing()
    seen = swing('[[sensor]]\nsignal = "pendulum.hinge.velocity"\nrate = "250Hz"\n'
                 '[[sensor]]\nsignal = "pendulum.hinge.position"\nlatency = "2ms"\n')
    check(len(truth) == len(seen) == 400, "400 records each")
    check(len(set(row[1] for row in truth)) > 300, "the pendulum swings")
    # Record k is the world at k ms (the first at 0).
    check(all(seen[k][1] == truth[k - k % 4][1] for k in range(400)),
          "the velocity is the truth at the last 4 ms mark, held")
    check(all(seen[k][0] == truth[max(k - 2, 0)][0] for k in range(400)), "the angle is the truth 2 ms before")
    print("  velocity held 4 ms a sample (250 Hz); angle 2 ms late, both exactly")


def test_a_record_replays_its_sensor_noise():
    # Recorded without --seed (the noise is the machine's randomness), the
    # replay reads the same noisy records: the record keeps the stream.
    path = os.path.join(tempfile.gettempdir(), "tcs-test-sensors-%d.mcap" % os.getpid())
    argv = ["head", "-n", "300", "/dev/tcs/pendulum/state"]
    try:
        with scenario_file(WORLD) as world:
            r = tcs("-q", "--record", path, "-w", world, "--", *argv, timeout=60)
            check(r.returncode == 0 and len(r.stdout.splitlines()) == 300, "a recorded run reads 300 records", r)
            p = tcs("-q", "--replay", path, "-w", world, "--", *argv, timeout=60)
            live = tcs("-q", "-w", world, "--", *argv, timeout=60)
    finally:
        if os.path.exists(path):
            os.unlink(path)
    check(p.returncode == 0 and "departs" not in p.stderr, "the replay keeps to the record", p)
    check(p.stdout == r.stdout, "the replay reads the recorded noise, byte for byte", p)
    check(live.stdout != r.stdout, "a live run without --seed reads other noise", live)
    print("  300 noisy records replayed byte for byte")


if __name__ == "__main__":
    main(globals())
