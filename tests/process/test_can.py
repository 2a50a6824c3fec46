"""SocketCAN in virtual time (docs/DESIGN.md §9, [[can]]): stock can-utils
programs, unmodified, on an emulated interface. A frame reaches a reader
when its last bit has crossed the bus at the declared bit rate, stuff bits
included (counted from the frame's bits by can_bits.py, from ISO 11898-1:
nothing is imported from tcs); frames queued behind one on the wire follow
it back to back; an MIT motor answers its commands and moves its joint;
CAN_RAW filters and loopback flags are the kernel's; CAN FD frames, receive
timestamps and the interface ioctls answer as on a real interface; frames
of signals carry the world out and efforts in; the trace holds every frame
with its times and who sent it, and exports the bus as candump's log."""

import json
import math
import os
import struct
import tempfile

from can_bits import fd_frame_bits, frame_bits, socketcan_frame_bits
from harness import SLACK, TCS_TRACE, check, main, need_tool, read_trace, run, scenario_file, tcs, trace_rows

BUS = """\
[sim]
step = "1ms"
model = "pendulum"

[[can]]
interface = "can0"
bitrate = "1Mbit/s"
"""

MOTOR = BUS + """
[[can.motor]]
protocol = "mit"
id = 1
joint = "pendulum.hinge"
"""

EPOCH = 1700000000


def dump_rows(text):
    """candump -t a lines: (time in µs since the epoch, id, data bytes)."""
    rows = []
    for line in text.splitlines():
        f = line.replace("TX - -", "").replace("RX - -", "").split()
        t = round((float(f[0].strip("()")) - EPOCH) * 1e6)
        rows.append((t, int(f[2], 16), bytes(int(x, 16) for x in f[4:]), "TX" in line))
    return rows


def run_sh(world, script, timeout=60):
    r = tcs("-q", "-m", "lockstep", "--epoch", str(EPOCH), "-w", world, "--", "sh", "-c", script, timeout=timeout)
    check(r.returncode == 0, "the programs end", r)
    return r


def need_can_utils():
    need_tool("candump", "can-utils")


def test_cansend_reaches_candump_when_its_last_bit_has():
    need_can_utils()
    with scenario_file(BUS) as world:
        script = "candump -t a -n 1 can0 & sleep 0.01; cansend can0 123#DEADBEEF; wait"
        r = run_sh(world, script)
        again = run_sh(world, script)
    rows = dump_rows(r.stdout)
    check(len(rows) == 1 and rows[0][1] == 0x123 and rows[0][2] == bytes.fromhex("DEADBEEF"), "one frame", r)
    bits = frame_bits(0x123, bytes.fromhex("DEADBEEF"))
    start = rows[0][0] - bits
    check(bits == 81, "123#DEADBEEF is 81 bits with its stuff bits")
    # Sent when sh's `sleep 0.01` ended: 10 ms and its timer slack (a normal
    # thread's). cansend's start-up takes no virtual time in lockstep but its
    # clock reads' (a spin's, 25 ns each with --epoch: docs/DESIGN.md §2),
    # which candump's stamps, whole µs, do not show.
    check(start == 10000 + SLACK // 1000, "sent at sleep 0.01's end and its slack, 10050 µs: at %d µs; arrived %d µs "
          "later" % (start, bits), r)
    check(r.stdout == again.stdout, "the same virtual times again", again)
    print("  123#DEADBEEF sent at %d µs, candump stamps it %d µs later (81 bits at 1 Mbit/s), on the epoch" %
          (start, bits))


def test_frames_queued_behind_each_other_take_their_bit_times_back_to_back():
    need_can_utils()
    with scenario_file(BUS) as world:
        r = run_sh(world, "candump -t a -n 10 can0 & sleep 0.01; cangen can0 -g 0 -n 10 -I 123 -L 8 -D i; wait")
    rows = dump_rows(r.stdout)
    check(len(rows) == 10, "10 frames", r)
    bits = [frame_bits(cid, data) for _, cid, data, _ in rows]
    gaps = [rows[i + 1][0] - rows[i][0] for i in range(9)]
    check(gaps == bits[1:], "each frame ends its own bit time after the one before: %s µs, bits %s" %
          (gaps, bits[1:]), r)
    print("  10 frames back to back: %d µs from the first's end to the last's = the sum of their bits" %
          sum(gaps))


def test_a_hundred_frames_a_millisecond_apart():
    need_can_utils()
    with scenario_file(BUS) as world:
        r = run_sh(world, "candump -t a -n 100 can0 & sleep 0.01; cangen can0 -g 1 -n 100 -I 42 -L 8 -D i; wait",
                   timeout=120)
    rows = dump_rows(r.stdout)
    check(len(rows) == 100 and [d[0] for _, _, d, _ in rows] == [i % 256 for i in range(100)],
          "100 frames in order", r)
    gaps = [rows[i + 1][0] - rows[i][0] - frame_bits(0x42, rows[i + 1][2]) + frame_bits(0x42, rows[i][2])
            for i in range(99)]
    check(all(g >= 1000 for g in gaps), "sent at least 1 ms apart (the send times, their bits taken out)", r)
    print("  100 frames at 1 ms: the last at %d µs" % rows[-1][0])


def test_an_mit_motor_answers_and_moves_its_joint():
    need_can_utils()
    with scenario_file(MOTOR) as world:
        r = run_sh(world, "candump -x -t a -n 6 can0 & sleep 0.01; cansend can0 001#FFFFFFFFFFFFFFFC; "
                   "sleep 0.2; cansend can0 001#8000800000000FFF; sleep 0.3; cansend can0 001#8000800000000FFF; wait")
    rows = dump_rows(r.stdout)
    check(len(rows) == 6, "three commands, three replies", r)
    for i in (1, 3, 5):
        t, cid, data, tx = rows[i]
        check(cid == 0 and len(data) == 6 and data[0] == 1 and not tx, "a 6-byte reply from motor 1 on id 0", r)
        check(t - rows[i - 1][0] == frame_bits(0, data), "sent when the command ended: %d µs later, its bits" %
              (t - rows[i - 1][0]), r)
        check(rows[i - 1][3], "the commands are local (TX), the replies not", r)
    position = int.from_bytes(rows[5][2][1:3], "big")
    torque = ((rows[5][2][4] & 0xF) << 8) | rows[5][2][5]
    check(position > 0x8000 + 1000, "5 N·m for 0.3 s has turned the joint (position 0x%04x)" % position, r)
    check(torque == 0xFFF, "the reply reports the torque applied: +5 N·m", r)
    print("  motor 1: FC, then 5 N·m: position field 0x%04x after 0.3 s" % position)


def test_filters_pass_what_they_match():
    need_can_utils()
    with scenario_file(BUS) as world:
        # Either filter (candump's default), and both (",j": CAN_RAW_JOIN_FILTERS).
        either = run_sh(world, "candump -t a -n 3 can0,120:7F0,300~7FF & sleep 0.01; for i in 300 121 125 12A; do "
                        "cansend can0 $i#01; done; wait")
        both = run_sh(world, "candump -t a -n 2 can0,120:7F0,125~7FF,j & sleep 0.01; for i in 110 121 125 12A; do "
                      "cansend can0 $i#01; done; wait")
    ids = [cid for _, cid, _, _ in dump_rows(either.stdout)]
    check(ids == [0x121, 0x125, 0x12A], "12x by the first, none by the inverted 300: %s" % [hex(i) for i in ids],
          either)
    ids = [cid for _, cid, _, _ in dump_rows(both.stdout)]
    check(ids == [0x121, 0x12A], "joined: 12x but not 125: %s" % [hex(i) for i in ids], both)


# The programs' shared start: a CAN_RAW socket bound to can0.
SOCK = """\
import select, socket, struct, time
def sock():
    s = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
    s.bind(("can0",))
    return s
"""

OVERTAKE = SOCK + """\
reader, first, second = sock(), sock(), sock()
frame = lambda cid, data: struct.pack("=IB3x8s", cid, len(data), data)
first.send(frame(0x700, bytes(8)))      # on the wire at once, alone
time.sleep(20e-6)                       # (sent together, 0x100 would win the first arbitration)
first.send(frame(0x600, bytes(8)))      # queued behind it (its own socket's order)
second.send(frame(0x100, bytes(8)))     # queued later, from another node, higher priority
t0 = time.monotonic_ns()
for _ in range(3):
    cid = struct.unpack("=I", reader.recv(16)[:4])[0]
    print(hex(cid), time.monotonic_ns() - t0)
"""


def test_a_high_priority_frame_overtakes_a_queued_low_priority_one():
    with scenario_file(BUS) as world, scenario_file(OVERTAKE) as prog:
        r = tcs("-q", "-m", "lockstep", "-w", world, "--", "python3", prog, timeout=60)
    check(r.returncode == 0, "the program ends", r)
    rows = [(int(a, 16), int(b)) for a, b in (line.split() for line in r.stdout.splitlines())]
    check([cid for cid, _ in rows] == [0x700, 0x100, 0x600],
          "0x700 (on the wire), then 0x100 (won the arbitration), then 0x600 (queued first)", r)
    bits = [frame_bits(cid, bytes(8)) for cid, _ in rows]
    ends = [t for _, t in rows]
    # Each ends its own bit time after the one before (1 µs a bit), the
    # first its bits after it was sent (less the few ns a clock read costs).
    check(ends[1] - ends[0] == bits[1] * 1000 and ends[2] - ends[1] == bits[2] * 1000,
          "back to back: %s ns apart, bits %s" % ([ends[1] - ends[0], ends[2] - ends[1]], bits[1:]), r)
    print("  0x700, then 0x100 overtaking 0x600: ends %s ns after the sends" % ends)


OWN = SOCK + """\
sender, own, other = sock(), sock(), sock()
own.setsockopt(socket.SOL_CAN_RAW, socket.CAN_RAW_RECV_OWN_MSGS, 1)
quiet = sock()
quiet.setsockopt(socket.SOL_CAN_RAW, socket.CAN_RAW_LOOPBACK, 0)
t0 = time.monotonic_ns()
sender.send(struct.pack("=IB3x8s", 0x123, 2, b"hi"))
own.send(struct.pack("=IB3x8s", 0x124, 2, b"me"))
quiet.send(struct.pack("=IB3x8s", 0x125, 2, b"no"))
for name, s in (("sender", sender), ("own", own), ("other", other)):
    got = []
    while select.select([s], [], [], 0.01)[0]:
        data, _, flags, _ = s.recvmsg(16)
        got.append("%x%s" % (struct.unpack("=I", data[:4])[0], "+own" if flags & socket.MSG_CONFIRM else ""))
    print(name, " ".join(got), (time.monotonic_ns() - t0) // 1000)
"""


def test_loopback_and_own_frames_as_the_kernel_delivers_them():
    with scenario_file(BUS) as world, scenario_file(OWN) as prog:
        r = tcs("-q", "-m", "lockstep", "--epoch", str(EPOCH), "-w", world, "--", "python3", prog, timeout=60)
    check(r.returncode == 0, "the program ends", r)
    lines = {f[0]: f[1:] for f in (line.split() for line in r.stdout.splitlines())}
    # Each socket sees the others' frames (loopback on), not its own unless
    # it asked (CAN_RAW_RECV_OWN_MSGS: flagged MSG_CONFIRM); a socket with
    # loopback off is heard by nobody on this machine. select() waits for
    # a frame in virtual time and ends at its timeout with none.
    check(lines["sender"][:-1] == ["124"], "the sender hears own's frame, not its own nor quiet's", r)
    check(lines["own"][:-1] == ["123", "124+own"], "own hears the sender's and its own, flagged", r)
    check(lines["other"][:-1] == ["123", "124"], "another socket hears both, not quiet's", r)
    # When each socket's select gave up, in µs after the sends: the three
    # frames went on the wire together, 0x123 winning the arbitration, then
    # 0x124; the sender's select waited for 0x124's last bit, then its
    # 10 ms timeout and that wait's timer slack. The other two found their
    # frames there and waited out the same timeout each, one after the
    # other. (The program's clock reads, a spin's 25 ns each with --epoch,
    # stay under the µs it prints.)
    heard = frame_bits(0x123, b"hi") + frame_bits(0x124, b"me")
    timeout = 10000 + SLACK // 1000
    ends = [int(lines[name][-1]) for name in ("sender", "own", "other")]
    check(ends == [heard + timeout, heard + 2 * timeout, heard + 3 * timeout],
          "select's timeouts end %s µs after the sends: 0x124's end (%d µs) and 10.05 ms each" % (ends, heard), r)


def test_the_trace_holds_each_frame_and_exports_the_bus_as_candump_logs_it():
    """candump -L under tcs-run and tcs-trace's candump export of the same
    run's trace print the same lines; each traced frame lasts its bits, and
    names its sender and what the motor made of it."""
    need_can_utils()
    with scenario_file(MOTOR) as world, tempfile.TemporaryDirectory() as tmp:
        trace = os.path.join(tmp, "can.mcap")
        r = tcs("-q", "-m", "lockstep", "--epoch", str(EPOCH), "-w", world, "-t", trace, "--", "sh", "-c",
                "candump -L -n 4 can0 & sleep 0.01; cansend can0 001#FFFFFFFFFFFFFFFC; cansend can0 001#0102; "
                "cangen can0 -e -n 1 -I 12345678 -L 0 -R; wait", timeout=60)
        check(r.returncode == 0, "the programs end", r)
        e = run([TCS_TRACE, "export", trace, "--format", "candump"])
        one = run([TCS_TRACE, "export", trace, "--format", "candump", "--topic", "/tcs/wire/can0"])
        none = run([TCS_TRACE, "export", trace, "--format", "candump", "--topic", "/tcs/wire/can9"])
        rows = trace_rows(trace, "/tcs/wire/can0")
        official = read_trace(trace)
        summary = run([TCS_TRACE, "summary", trace])
        summary_json = run([TCS_TRACE, "summary", "--json", trace])
    check(official["topics"].get("/tcs/wire/can0") == 4, "Foxglove's readers decode the bus's 4 frames", official)
    check(e.returncode == 0 and e.stdout == r.stdout and len(r.stdout.splitlines()) == 4,
          "the export is what candump -L printed, line for line:\n%s\n%s" % (r.stdout, e.stdout), e)
    check(one.stdout == e.stdout, "--topic of the one bus: the same", one)
    check(none.returncode == 2 and "can9" in none.stderr and "/tcs/wire/can0" in none.stderr,
          "a topic the trace lacks: exit 2 naming it and the buses it has", none)
    check([(x["from"], int(x["can_id"]), x["note"]) for x in rows] ==
          [("cansend", 1, ""), ("motor 1", 0, ""), ("cansend", 1, "motor 1: a frame of 2 bytes, not 8: ignored"),
           ("cangen", 0x12345678 | 0xC0000000, "")],
          "senders, ids (SocketCAN's flags) and the motor's refusal: %s" % rows)
    # Each lasts its bits at 1 µs, the extended remote frame (cangen -e -R)
    # included; the summary's busy time is their sum.
    busy = 0
    for x in rows:
        data = bytes(int(x["data[%d]" % i]) for i in range(int(x["len"])))
        bits = socketcan_frame_bits(int(x["can_id"]), data)
        check(int(x["v_end_ns"]) - int(x["v_start_ns"]) == bits * 1000, "%s lasts its %d bits" % (x, bits))
        busy += bits * 1000
    check("  can0: 4 frames, 16 bytes; busy " in summary.stdout and "; 1 refused by a device" in summary.stdout,
          "tcs-trace summary counts the bus's frames, their data and the refusal", summary)
    wire = [w for w in json.loads(summary_json.stdout)["wires"] if w["name"] == "can0"]
    check(len(wire) == 1 and (wire[0]["messages"], wire[0]["bytes"], wire[0]["busy_ns"]) == (4, 16, busy),
          "summary --json: 4 frames, 16 bytes, busy their bits' %d ns: %s" % (busy, wire), summary_json)
    check(all(": %s (pid " % name in summary.stdout for name in ("candump", "cansend", "cangen")),
          "the shell's children named by the programs they exec'd", summary)
    print("  candump -L and tcs-trace export --format candump: the same %d lines" % len(rows))


FD_BUS = """\
[sim]
step = "1ms"
model = "pendulum"

[[can]]
interface = "can1"
bitrate = "1Mbit/s"
data_bitrate = "4Mbit/s"
"""

FD = """\
import fcntl, socket, struct, time
s = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
def ifreq(code, fmt, *a):
    size = struct.calcsize(fmt)
    return struct.unpack(fmt, fcntl.ioctl(s, code, struct.pack(fmt, *a) + bytes(40 - size))[:size])
index = ifreq(0x8933, "16si", b"can1", 0)[1]                              # SIOCGIFINDEX
print("name", ifreq(0x8910, "16si", b"", index)[0].rstrip(b"\\0").decode())  # SIOCGIFNAME
print("mtu", ifreq(0x8921, "16si", b"can1", 0)[1])                           # SIOCGIFMTU
print("flags", ifreq(0x8913, "16sh", b"can1", 0)[1])                         # SIOCGIFFLAGS
def sock():
    k = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
    k.setsockopt(socket.SOL_CAN_RAW, socket.CAN_RAW_FD_FRAMES, 1)
    k.setsockopt(socket.SOL_SOCKET, 35, 1)                                   # SO_TIMESTAMPNS
    k.bind(("can1",))
    return k
reader, writer = sock(), sock()
writer.send(struct.pack("=IBBBB64s", 0x123, 12, 1, 0, 0, bytes(range(12))))  # CANFD_BRS
writer.send(struct.pack("=IB3x8s", 0x124, 2, b"hi"))
for _ in range(2):
    data, cmsgs, _, _ = reader.recvmsg(72, 64)
    now = time.monotonic_ns()
    can_id, length, flags = struct.unpack("=IBB", data[:6])
    stamp = [struct.unpack("=qq", d) for level, kind, d in cmsgs if kind == 35]  # SCM_TIMESTAMPNS
    ns = struct.unpack("=qq", fcntl.ioctl(reader, 0x8907, bytes(16)))             # SIOCGSTAMPNS
    us = struct.unpack("=qq", fcntl.ioctl(reader, 0x8906, bytes(16)))             # SIOCGSTAMP
    print("frame", len(data), can_id, length, flags, data[8:8 + length].hex(), stamp[0][0] * 10**9 + stamp[0][1],
          ns[0] * 10**9 + ns[1], us[0] * 10**6 + us[1], now)
"""


def test_fd_frames_timestamps_and_the_interface_ioctls():
    with scenario_file(FD_BUS) as world, scenario_file(FD) as prog, tempfile.TemporaryDirectory() as tmp:
        trace = os.path.join(tmp, "fd.mcap")
        r = tcs("-q", "-m", "lockstep", "--epoch", str(EPOCH), "-w", world, "-t", trace, "--", "python3", prog,
                timeout=60)
        check(r.returncode == 0, "the program ends", r)
        rows = trace_rows(trace, "/tcs/wire/can1")
        check(read_trace(trace)["topics"].get("/tcs/wire/can1") == 2, "Foxglove's readers decode the FD frame too")
    v = {f[0]: f[1:] for f in (line.split() for line in r.stdout.splitlines()) if f[0] != "frame"}
    frames = [f[1:] for f in (line.split() for line in r.stdout.splitlines()) if f[0] == "frame"]
    check(v["name"] == ["can1"] and v["mtu"] == ["72"], "SIOCGIFNAME of SIOCGIFINDEX's index; an FD interface's MTU", r)
    check(int(v["flags"][0]) & 0x41 == 0x41, "IFF_UP and IFF_RUNNING", r)
    check(len(frames) == 2 and frames[0][:5] == ["72", str(0x123), "12", "5", bytes(range(12)).hex()],
          "the FD frame: 72 bytes, its 12 of data, CANFD_BRS with CANFD_FDF as the kernel marks it", r)
    check(frames[1][:5] == ["16", str(0x124), "2", "0", "6869"], "a classic frame on an FD socket: 16 bytes", r)
    for f, t in zip(frames, rows):
        stamp, ns, us = int(f[5]), int(f[6]), int(f[7])
        check(stamp == ns == EPOCH * 10**9 + int(t["v_end_ns"]) and us == ns // 1000,
              "SCM_TIMESTAMPNS and SIOCGSTAMPNS are the frame's end on the wire on the epoch, SIOCGSTAMP in µs", r)
        # The clock read right after the recvmsg that waited for the frame
        # is its end, exactly: a frame received ends a spin (docs/DESIGN.md
        # §2), so the read costs nothing. (CLOCK_MONOTONIC is 100000 s at
        # virtual 0 with --epoch.)
        check(int(f[8]) == 100000 * 10**9 + int(t["v_end_ns"]),
              "the clock read after recvmsg is the frame's end: %s, %d" % (f[8], int(t["v_end_ns"])), r)
    # With BRS: its arbitration and tail at 1 Mbit/s, from ESI to the CRC's
    # end at the data phase's 4 Mbit/s; the classic frame at 1 Mbit/s.
    fd_ns = int(rows[0]["v_end_ns"]) - int(rows[0]["v_start_ns"])
    nominal, data = fd_frame_bits(0x123, bytes(range(12)))
    check(rows[0]["fd"] == "true" and rows[0]["fd_flags"] == "1" and fd_ns == nominal * 1000 + data * 250,
          "its %d bits at 1 Mbit/s and %d at 4 Mbit/s: %d ns; %d on the wire" %
          (nominal, data, nominal * 1000 + data * 250, fd_ns), rows)
    classic_ns = int(rows[1]["v_end_ns"]) - int(rows[1]["v_start_ns"])
    check(classic_ns == frame_bits(0x124, b"hi") * 1000, "the classic frame: its bits at 1 Mbit/s (%d ns)" %
          classic_ns, rows)
    print("  FD frame of 12 bytes with BRS: %.2f µs on the wire; stamps equal the trace's ends" % (fd_ns / 1e3))


SIGNALS = BUS + """
[[can.frame]]
id = 0x100
rate = "100Hz"
byte_order = "little"
fields = [{ signal = "pendulum.hinge.position", type = "float32" },
          { signal = "pendulum.hinge.velocity", type = "int16", scale = 0.001 }]

[[can.frame]]
id = 0x200
command = true
byte_order = "little"
fields = [{ signal = "pendulum.hinge.effort", type = "int16", scale = 0.001 }]
"""

SIGNALS_PROG = SOCK + """\
import sys
s = sock()
if len(sys.argv) > 1:
    s.send(struct.pack("=IB3x8s", 0x200, 2, struct.pack("<h", int(float(sys.argv[1]) * 1000))))
for _ in range(30):
    data = s.recv(16)
    can_id, length = struct.unpack("=IB", data[:5])
    if can_id == 0x100:
        position, velocity = struct.unpack("<fh", data[8:14])
        print(position, velocity * 0.001)
"""


def test_frames_of_signals_carry_the_world_out_and_efforts_in():
    with scenario_file(SIGNALS) as world, scenario_file(SIGNALS_PROG) as prog, \
            tempfile.TemporaryDirectory() as tmp:
        trace = os.path.join(tmp, "signals.mcap")
        still = tcs("-q", "-m", "lockstep", "-w", world, "--", "python3", prog, timeout=60)
        pushed = tcs("-q", "-m", "lockstep", "-w", world, "-t", trace, "--", "python3", prog, "2.0", timeout=60)
        check(still.returncode == 0 and pushed.returncode == 0, "the programs end", pushed)
        frames = trace_rows(trace, "/tcs/wire/can0")
        steps = trace_rows(trace, "/tcs/step")
    at_rest = [tuple(map(float, line.split())) for line in still.stdout.splitlines()]
    moved = [tuple(map(float, line.split())) for line in pushed.stdout.splitlines()]
    check(len(at_rest) == 30 and all(p == 0 and w == 0 for p, w in at_rest), "hanging still: 0 and 0", still)
    check(len(moved) == 30, "30 frames read", pushed)
    # 2 N·m on the hanging rod (1 kg, 1 m: I = m l^2 / 3 about the hinge,
    # gravity's torque m g l/2 sin θ against it) from the command's first
    # step on: between two frames 10 ms apart the velocity grows by the
    # acceleration's integral, here by the trapezoid over the frames'
    # positions. Each velocity is in the frame to the nearest 0.001 rad/s
    # (±0.0005 each, so 0.001 on a difference). The acceleration falls
    # monotonically as the rod rises, so ODE's sum over the 10 steps and
    # the trapezoid both lie between its ends' values times 10 ms: apart
    # by half their difference times 10 ms at most.
    inertia, weight = 1.0 / 3, 1.0 * 9.81 * 0.5

    def accel(angle):
        return (2.0 - weight * math.sin(angle)) / inertia

    for a, b in zip(moved[1:], moved[2:]):
        want = 0.010 * (accel(a[0]) + accel(b[0])) / 2
        off = 0.001 + 0.010 * abs(accel(a[0]) - accel(b[0])) / 2
        check(abs((b[1] - a[1]) - want) <= off, "2 N·m from the command frame: the velocity grows by %.4f rad/s in "
              "10 ms, %.4f from the physics (± %.4f)" % (b[1] - a[1], want, off), pushed)
    sensor = [x for x in frames if int(x["can_id"]) == 0x100]
    check(all(x["from"] == "frame 0x100" for x in sensor), "sent by the world's frame", frames[:3])
    starts = [int(x["v_start_ns"]) for x in sensor]
    check(starts[:5] == [0, 10000000, 20000000, 30000000, 40000000], "at 100 Hz from 0: %s" % starts[:5])
    # Each carries the joint as the world had it when it was sent: the
    # step that ended at its start.
    position = {int(x["v_ns"]): float(x["joint.pendulum.hinge.position"]) for x in steps}
    position[0] = 0.0
    on_bus = []
    for x in sensor:
        data = bytes(int(x["data[%d]" % i]) for i in range(6))
        p, w = struct.unpack("<fh", data)
        want = struct.unpack("<f", struct.pack("<f", position[int(x["v_start_ns"])]))[0]
        check(p == want, "position %r in the frame at %s ns, %r in the world" % (p, x["v_start_ns"], want))
        on_bus.append((p, w * 0.001))
    # The program read them from when its socket was bound (its start-up
    # takes the virtual time of its clock reads, this machine's).
    first = next((k for k in range(len(on_bus) - 29) if on_bus[k:k + 30] == moved), None)
    check(first is not None, "the program read the frames on the bus, in order, from the first after its bind: "
          "%s against %s" % (moved[:3], on_bus[:4]))
    print("  0x100 at 100 Hz: position and velocity of the world; 0x200 with 2 N·m: velocity %.3f rad/s after 80 ms"
          % moved[8][1])


def test_a_bad_can_table_exits_2_at_its_line():
    with scenario_file(BUS.replace('bitrate = "1Mbit/s"', 'bitrate = "5Mbit/s"')) as world:
        r = tcs("-q", "-w", world, "--", "true", timeout=30)
    check(r.returncode == 2 and (":7:" in r.stderr), "exit 2 naming FILE:LINE", r)


if __name__ == "__main__":
    main(globals())
