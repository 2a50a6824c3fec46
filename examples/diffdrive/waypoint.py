#!/usr/bin/env python3
"""waypoint: drive a two-wheeled robot to a point on the floor and stop
there, as a plain Python program that knows nothing of tcs (standard
library only). The robot is examples/diffdrive/diffdrive.sdf: two driven
wheels of radius 0.05 m on a 0.25 m track, their motors limited to
0.5 N m, and a caster.

Each cycle it reads a state record, "x y z qw qx qy qz left right" (the
chassis pose in the world, m and a unit quaternion, of the frame at the
middle of the wheels' axle, and the wheels' speeds, rad/s, positive
forward), and writes a "left right" line of wheel torques (N m). It
paces itself with absolute deadlines on the monotonic clock. On the
robot the two paths would be its localisation and its motor driver.

  waypoint.py [--rate HZ] [--seconds S] [--state PATH] [--effort PATH]
              [--tolerance M] X Y

Control, a go-to-goal law over a wheel-speed loop: the forward speed asked
for grows with the distance left (up to 0.4 m/s, ramped at 1 m/s^2) and
shrinks as the heading error grows; the turn rate asked for is
proportional to the heading error; the two wheels' speeds follow from
them, and each wheel's torque comes from a PI loop on its speed error
(which brakes the wheels to a stop when the speeds asked for are zero).
Near the goal it may back up rather than turn round; within 2 cm it stops, and
starts again only if pushed 6 cm away.

At the end (after --seconds, or on SIGTERM or SIGINT) it prints how it
did, as key=value pairs: when it first came within --tolerance of the
goal (reached_at, seconds from its start, -1 if never), its final
distance (m), when it first stopped there (stopped_at, -1 if never) and
the farthest it was from the goal after that (worst_after_stop, -1), and
the lowest and highest chassis heights it read (z_min, z_max, m).
"""

import argparse
import math
import signal
import sys
import time

# The robot (diffdrive.sdf).
WHEEL_RADIUS = 0.05   # m
TRACK = 0.25          # m, between the wheels' contacts
EFFORT_LIMIT = 0.5    # N m, each motor

# The law.
V_MAX = 0.4           # m/s
ACCEL = 1.0           # m/s^2, the forward speed's ramp
K_DIST = 1.2          # 1/s: forward speed per metre left
W_MAX = 2.0           # rad/s, turn rate
K_HEADING = 3.0       # 1/s: turn rate per radian of heading error
K_WHEEL = 0.08        # N m per rad/s of wheel speed error
KI_WHEEL = 0.6        # N m per rad of accumulated wheel speed error
STOP_AT = 0.02        # m
RESTART_AT = 0.06     # m
REVERSE_WITHIN = 0.3  # m: nearer than this it may back up

stop = False


def on_signal(signum, frame):
    global stop
    stop = True


def wrap_pi(a):
    return math.atan2(math.sin(a), math.cos(a))


def clamp(v, lim):
    return lim if v > lim else -lim if v < -lim else v


def yaw_of(qw, qx, qy, qz):
    return math.atan2(2 * (qw * qz + qx * qy), 1 - 2 * (qy * qy + qz * qz))


class GoToGoal:
    def __init__(self, gx, gy, dt):
        self.gx, self.gy, self.dt = gx, gy, dt
        self.v_ref = 0.0
        self.stopped = False
        self.held = [0.0, 0.0]  # the speed loops' integral terms, N m

    def torques(self, x, y, yaw, w_left, w_right):
        dx, dy = self.gx - x, self.gy - y
        dist = math.hypot(dx, dy)
        if self.stopped and dist > RESTART_AT:
            self.stopped = False
        elif not self.stopped and dist < STOP_AT:
            self.stopped = True
        if self.stopped:
            v, w = 0.0, 0.0
        else:
            err = wrap_pi(math.atan2(dy, dx) - yaw)
            v = min(V_MAX, K_DIST * dist) * math.cos(err)
            if dist < REVERSE_WITHIN and math.cos(err) < 0:
                err = wrap_pi(err + math.pi)  # the goal is behind: back up to it
            else:
                v = max(v, 0.0)
            w = clamp(K_HEADING * err, W_MAX)
        if self.stopped:
            # Stopped: the wheels braked, and what the integral terms held
            # let go (on a level floor the robot stays put unpowered).
            self.v_ref = 0.0
            self.held = [h * 0.9 for h in self.held]
        else:
            self.v_ref += clamp(v - self.v_ref, ACCEL * self.dt)
        v = self.v_ref
        ref_left = (v - w * TRACK / 2) / WHEEL_RADIUS
        ref_right = (v + w * TRACK / 2) / WHEEL_RADIUS
        out = []
        for k, (ref, speed) in enumerate(((ref_left, w_left), (ref_right, w_right))):
            # A PI speed loop: the integral term carries what the wheel
            # needs to keep turning (a tyre scrubbing round a turn), held
            # within the motor's limit.
            self.held[k] = clamp(self.held[k] + KI_WHEEL * (ref - speed) * self.dt, EFFORT_LIMIT)
            out.append(clamp(K_WHEEL * (ref - speed) + self.held[k], EFFORT_LIMIT))
        return out[0], out[1], dist


def main():
    prog = sys.argv[0]
    ap = argparse.ArgumentParser(description="Drive a two-wheeled robot to a waypoint and stop there.")
    ap.add_argument("x", type=float, help="the waypoint's x, m")
    ap.add_argument("y", type=float, help="the waypoint's y, m")
    ap.add_argument("-r", "--rate", type=float, default=100.0, metavar="HZ")
    ap.add_argument("-s", "--seconds", type=float, default=0.0, metavar="S",
                    help="stop after S seconds (0: at SIGTERM or SIGINT)")
    ap.add_argument("--state", default="/dev/tcs/diffdrive/state", metavar="PATH")
    ap.add_argument("--effort", default="/dev/tcs/diffdrive/effort", metavar="PATH")
    ap.add_argument("--tolerance", type=float, default=0.1, metavar="M")
    p = ap.parse_args()
    if p.rate <= 0:
        print(f"{prog}: --rate must be positive", file=sys.stderr)
        return 2
    try:
        state = open(p.state, "r")
        effort = open(p.effort, "w")
    except OSError as e:
        print(f"{prog}: cannot open {e.filename}: {e.strerror}", file=sys.stderr)
        return 1
    signal.signal(signal.SIGTERM, on_signal)
    signal.signal(signal.SIGINT, on_signal)

    period = int(1e9 / p.rate)
    law = GoToGoal(p.x, p.y, period / 1e9)
    start = time.monotonic()
    next_ns = time.monotonic_ns()
    reached_at = stopped_at = -1.0
    worst_after_stop = 0.0
    dist = math.nan
    z_low, z_high = math.inf, -math.inf
    cycles = 0
    while not stop and (p.seconds <= 0 or time.monotonic() - start < p.seconds):
        line = state.readline()
        try:
            x, y, z, qw, qx, qy, qz, w_left, w_right = (float(f) for f in line.split()[:9])
        except ValueError:
            if stop:
                break
            print(f"{prog}: bad state record {line!r}", file=sys.stderr)
            return 1
        left, right, dist = law.torques(x, y, yaw_of(qw, qx, qy, qz), w_left, w_right)
        effort.write("%.6f %.6f\n" % (left, right))
        effort.flush()
        cycles += 1
        z_low, z_high = min(z_low, z), max(z_high, z)
        if reached_at < 0 and dist < p.tolerance:
            reached_at = time.monotonic() - start
        if stopped_at < 0 and law.stopped:
            stopped_at = time.monotonic() - start
        if stopped_at >= 0:
            worst_after_stop = max(worst_after_stop, dist)

        next_ns += period
        time.sleep(max(0, next_ns - time.monotonic_ns()) / 1e9)
    try:
        effort.write("0 0\n")
        effort.flush()
    except OSError:
        pass
    elapsed = time.monotonic() - start
    print("waypoint: %d cycles in %.3f s; goal (%g, %g) %s; %.3f m from it at the end"
          % (cycles, elapsed, p.x, p.y,
             "reached at %.2f s" % reached_at if reached_at >= 0 else "NOT reached", dist))
    print("reached_at=%.3f distance=%.4f stopped_at=%.3f worst_after_stop=%.4f z_min=%.6f z_max=%.6f cycles=%d"
          % (reached_at, dist, stopped_at, worst_after_stop if stopped_at >= 0 else -1, z_low, z_high, cycles))
    return 0


if __name__ == "__main__":
    sys.exit(main())
