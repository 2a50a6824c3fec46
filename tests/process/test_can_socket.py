"""What a CAN_RAW socket promises beyond its frames' bit times (docs/DESIGN.md
§9, SocketCAN): its transmit queue holds 10 frames, then send fails with
ENOBUFS; SCM_TIMESTAMPING's software stamp is the frame's last bit on the
virtual CLOCK_REALTIME; SO_RXQ_OVFL counts the frames a full receive queue
dropped, as the kernel's CAN_RAW does; the error mask is the kernel's;
a forked child's CAN fds are opened again, unbound, with the default
options, and work. The programs are Python's socket module on the
emulated can0 (can_prelude.py); expected times are the frames' bits at
1 Mbit/s (can_bits.py, from ISO 11898-1) after times the programs sleep
to, in lockstep with --no-slack."""

from can_bits import standard_frame_bits
from can_prelude import PRELUDE
from harness import check, main, scenario_file, tcs

BUS = """\
[sim]
step = "1ms"
model = "pendulum"

[[can]]
interface = "can0"
bitrate = "1Mbit/s"
"""

EPOCH = 1700000000
BIT_NS = 1000  # 1 Mbit/s


def run_program(text, timeout=60):
    with scenario_file(BUS) as world, scenario_file(PRELUDE + text) as prog:
        r = tcs("-q", "-m", "lockstep", "--no-slack", "--epoch", str(EPOCH), "-w", world, "--", "python3", prog,
                timeout=timeout)
    check(r.returncode == 0, "the program ends", r)
    return r


def lines(r):
    """Each output line's first word -> the rest."""
    return {f[0]: f[1:] for f in (line.split() for line in r.stdout.splitlines()) if f}


QUEUE = """\
s, other, reader = sock(), sock(), sock()
serial = 0
def burst(k, can_id, limit=100):
    # Sends until the first failure; each frame carries its serial number.
    global serial
    ok = []
    for _ in range(limit):
        try:
            k.send(frame(can_id, struct.pack("<I", serial)))
        except OSError as e:
            serial += 1
            return ok, errno.errorcode[e.errno]
        ok.append(serial)
        serial += 1
    return ok, "none"
t0 = (time.clock_gettime_ns(time.CLOCK_MONOTONIC) // 10**6 + 10) * 10**6
sleep_until(CLOCK_MONOTONIC, t0)
accepted = []
for name, k, can_id, at in (("burst", s, 0x123, 0), ("other", other, 0x124, 0), ("drained", s, 0x123, 100 * 10**6)):
    if at:
        sleep_until(CLOCK_MONOTONIC, t0 + at)
    ok, err = burst(k, can_id)
    accepted += ok
    out(name, len(ok), err)
sleep_until(CLOCK_MONOTONIC, t0 + 200 * 10**6)   # the last burst has arrived too
reader.setblocking(False)
got = []
while True:
    try:
        got.append(struct.unpack("<I", unframe(reader.recv(16))[1])[0])
    except BlockingIOError:
        break
out("accepted", *sorted(accepted))
out("received", *sorted(got))
"""


def test_a_sockets_transmit_queue_holds_10_frames_then_send_fails_with_enobufs():
    """A burst at one instant queues 10 frames, and the 11th send fails with
    ENOBUFS; another socket has a queue of its own; once the bus has sent
    them all, there is room for 10 again. Every frame accepted reaches a
    reader, and no refused one does."""
    r = run_program(QUEUE)
    v = lines(r)
    check(v["burst"] == ["10", "ENOBUFS"], "a burst: 10 queued, then ENOBUFS: %s" % v["burst"], r)
    check(v["other"] == ["10", "ENOBUFS"], "another socket queues its own 10: %s" % v["other"], r)
    check(v["drained"] == ["10", "ENOBUFS"], "all sent: 10 places again: %s" % v["drained"], r)
    check(v["received"] == v["accepted"] and len(v["accepted"]) == 30,
          "the reader gets the 30 frames accepted, none refused", r)
    print("  10, 10 on another socket, 10 again once all are sent")


REFILL = """\
s = sock()
def fill():
    n = 0
    while True:
        try:
            s.send(frame(0x123, bytes(4)))
            n += 1
        except OSError as e:
            return n, errno.errorcode[e.errno]
bits_ns = int(sys.argv[1])
t0 = (time.clock_gettime_ns(time.CLOCK_MONOTONIC) // 10**6 + 10) * 10**6
sleep_until(CLOCK_MONOTONIC, t0)
out("burst", *fill())
for k in range(4):
    sleep_until(CLOCK_MONOTONIC, t0 + k * bits_ns + bits_ns // 2)   # half-way through frame k
    out("mid%d" % k, *fill())
"""


def test_a_full_queue_takes_one_frame_for_each_frame_the_bus_sends():
    """A frame leaves its socket's queue when it starts on the wire (the
    queue holds frames waiting, as a netdev's does; those sent at one
    instant still contend for the bus then, so a burst queues 10). So a
    full queue refilled half-way through each of the first frames on the
    wire takes exactly one more each time: one frame goes out each frame
    time. (tcs took 0, then 2: it put a frame on the wire only at the end
    of the frame before it, which held its place in the queue till then.)"""
    bits = standard_frame_bits(0x123, bytes(4))
    with scenario_file(BUS) as world, scenario_file(PRELUDE + REFILL) as prog:
        r = tcs("-q", "-m", "lockstep", "--no-slack", "-w", world, "--", "python3", prog, str(bits * BIT_NS),
                timeout=60)
    check(r.returncode == 0, "the program ends", r)
    v = lines(r)
    taken = [int(v["mid%d" % k][0]) for k in range(4)]
    check(v["burst"] == ["10", "ENOBUFS"], "a burst: 10", r)
    check(taken == [1, 1, 1, 1], "half-way through frames 1 to 4, room for one more each time: %s" % taken, r)


STAMPS = """\
reader, bare, sender = sock(), sock(), sock()
reader.setsockopt(socket.SOL_SOCKET, SO_TIMESTAMPING, SOF_RX_SOFTWARE | SOF_SOFTWARE)
bare.setsockopt(socket.SOL_SOCKET, SO_TIMESTAMPING, SOF_RX_SOFTWARE)   # generated, not reported
t = int(sys.argv[1]) * 10**9 + 50 * 10**6
sleep_until(CLOCK_REALTIME, t)
out("sent_at", t)
sender.send(frame(0x2A5, bytes([1, 2, 3])))
sender.send(frame(0x2A6, bytes([0xFF] * 8)))
for name, k in (("reader", reader), ("bare", bare)):
    for _ in range(2):
        raw, cmsgs, _, _ = k.recvmsg(16, 256)
        stamp = [struct.unpack("=6q", d) for d in stamps(cmsgs, SO_TIMESTAMPING)]
        out(name, hex(unframe(raw)[0]), len(cmsgs), *[x for s in stamp for x in s])
"""


def test_scm_timestampings_software_stamp_is_the_frames_last_bit_on_the_realtime_clock():
    """Two frames sent at a CLOCK_REALTIME instant the program slept to:
    SCM_TIMESTAMPING's first timespec is when each one's last bit crossed
    the bus (the first's bits, then the second's behind it), its other two
    (hardware) are zero; a socket that asks for stamps to be generated but
    not reported (SOF_TIMESTAMPING_RX_SOFTWARE without _SOFTWARE) gets no
    cmsg, as from the kernel (net/socket.c, __sock_recv_timestamp)."""
    with scenario_file(BUS) as world, scenario_file(PRELUDE + STAMPS) as prog:
        r = tcs("-q", "-m", "lockstep", "--no-slack", "--epoch", str(EPOCH), "-w", world, "--", "python3", prog,
                str(EPOCH), timeout=60)
    check(r.returncode == 0, "the program ends", r)
    rows = [line.split() for line in r.stdout.splitlines()]
    sent = int(rows[0][1])
    first = sent + standard_frame_bits(0x2A5, bytes([1, 2, 3])) * BIT_NS
    second = first + standard_frame_bits(0x2A6, bytes([0xFF] * 8)) * BIT_NS
    reader = [row[1:] for row in rows if row[0] == "reader"]
    want = [["0x2a5", "1", str(first // 10**9), str(first % 10**9), "0", "0", "0", "0"],
            ["0x2a6", "1", str(second // 10**9), str(second % 10**9), "0", "0", "0", "0"]]
    check(reader == want, "SCM_TIMESTAMPING: the last bits' times %s, got %s" % (want, reader), r)
    bare = [row[1:] for row in rows if row[0] == "bare"]
    check(bare == [["0x2a5", "0"], ["0x2a6", "0"]], "no stamp reported without SOF_TIMESTAMPING_SOFTWARE: %s" % bare, r)
    print("  stamps %d and %d ns after the send: the frames' bits at 1 Mbit/s" % (first - sent, second - sent))


OVERFLOW = """\
reader, sender = sock(), sock()
reader.setsockopt(socket.SOL_SOCKET, SO_RXQ_OVFL, 1)
reader.setblocking(False)
def send_all(first, n):
    # Frames numbered first.., sent as fast as the queue takes them.
    k = first
    while k < first + n:
        try:
            sender.send(frame(0x100, struct.pack("<I", k)))
            k += 1
        except OSError as e:
            if e.errno != errno.ENOBUFS:
                raise
            time.sleep(0.001)
    time.sleep(0.01)   # the last has arrived
def drain():
    while True:
        try:
            raw, cmsgs, _, _ = reader.recvmsg(16, 64)
        except BlockingIOError:
            return
        counts = [struct.unpack("=I", d)[0] for d in stamps(cmsgs, SO_RXQ_OVFL)]
        out("frame", struct.unpack("<I", unframe(raw)[1])[0], *counts)
send_all(0, int(sys.argv[1]))   # the reader reads none of them meanwhile
drain()
send_all(int(sys.argv[1]), 3)
drain()
"""


def test_so_rxq_ovfl_counts_the_frames_a_full_receive_queue_dropped():
    """A reader that reads nothing while 3000 frames pass loses those its
    receive queue has no room for. As the kernel's (net/core/sock.c sets
    each queued frame's count to the socket's drops so far; net/socket.c
    reports it only when it is not 0): a frame read carries no SO_RXQ_OVFL
    before the first drop, and afterwards the number of frames dropped
    before it, which is how many of the numbered frames are missing before
    it. Frames sent after the reader caught up carry the total."""
    n = 3000
    with scenario_file(BUS) as world, scenario_file(PRELUDE + OVERFLOW) as prog:
        r = tcs("-q", "-m", "lockstep", "-w", world, "--", "python3", prog, str(n), timeout=120)
    check(r.returncode == 0, "the program ends", r)
    got = [[int(x) for x in line.split()[1:]] for line in r.stdout.splitlines() if line.startswith("frame ")]
    numbers = [g[0] for g in got]
    check(numbers == sorted(set(numbers)) and numbers[-3:] == [n, n + 1, n + 2],
          "in order, the three sent after the drain all there", r)
    # (A precondition, not the contract: a receive queue of any socket
    # buffer's size fills long before 3000 frames.)
    check(len(numbers) < n + 3, "some frames were dropped (%d of %d read)" % (len(numbers), n + 3), r)
    for i, g in enumerate(got):
        missing = g[0] - i
        want = [g[0], missing] if missing else [g[0]]
        check(g == want, "frame %d, %d missing before it: SO_RXQ_OVFL %s, got %s" % (g[0], missing, want[1:], g[1:]),
              r)
    print("  %d of %d frames read; SO_RXQ_OVFL %d on the first after the gap, %d at the end" %
          (len(numbers), n + 3, next(g[1] for g in got if len(g) > 1), got[-1][1]))


ERRORS = """\
CAN_ERR_FLAG, CAN_ERR_MASK = 0x20000000, 0x1FFFFFFF
data, errors_only, error_filter, sender = sock(), sock(), sock(), sock()
data.setsockopt(SOL_CAN_RAW, CAN_RAW_ERR_FILTER, struct.pack("=I", 0xFFFFFFFF))
out("mask", hex(data.getsockopt(SOL_CAN_RAW, CAN_RAW_ERR_FILTER) & 0xFFFFFFFF))
try:
    data.setsockopt(SOL_CAN_RAW, CAN_RAW_ERR_FILTER, b"\\xff\\xff")
    out("short", "accepted")
except OSError as e:
    out("short", errno.errorcode[e.errno])
errors_only.setsockopt(SOL_CAN_RAW, CAN_RAW_FILTER, b"")
errors_only.setsockopt(SOL_CAN_RAW, CAN_RAW_ERR_FILTER, struct.pack("=I", CAN_ERR_MASK))
error_filter.setsockopt(SOL_CAN_RAW, CAN_RAW_FILTER, struct.pack("=II", 0, CAN_ERR_FLAG))
sender.send(frame(0x123, b"\\x01"))
sender.send(frame(0x80000000 | 0x1234567, b"\\x02"))
for name, k in (("data", data), ("errors_only", errors_only), ("error_filter", error_filter)):
    ids = []
    while select.select([k], [], [], 0.02)[0]:
        ids.append(hex(unframe(k.recv(16))[0]))
    out(name, *ids)
"""


def test_the_error_mask_is_the_kernels():
    """CAN_RAW_ERR_FILTER keeps only the error classes (CAN_ERR_MASK: the
    kernel's raw_setsockopt masks it) and takes exactly a can_err_mask_t
    (else EINVAL); it selects error frames, so a socket with it still gets
    the data frames its filters pass, one with no filters but an error mask
    gets none on a bus without errors, and a filter whose mask holds
    CAN_ERR_FLAG is an error-frame filter that no data frame meets
    (af_can.c puts it on the error list)."""
    r = run_program(ERRORS)
    v = lines(r)
    check(v["mask"] == ["0x1fffffff"], "getsockopt: the mask set, less what CAN_ERR_MASK leaves out: %s" % v["mask"],
          r)
    check(v["short"] == ["EINVAL"], "a 2-byte error mask: EINVAL", r)
    check(v["data"] == ["0x123", "0x81234567"], "an error mask leaves data frames to the filters: %s" % v["data"], r)
    check(v["errors_only"] == [] and v["error_filter"] == [],
          "no data frame for error frames' subscribers: %s, %s" % (v["errors_only"], v["error_filter"]), r)


FORK = """\
p = sock()
p.setsockopt(SOL_CAN_RAW, CAN_RAW_RECV_OWN_MSGS, 1)
p.setsockopt(SOL_CAN_RAW, CAN_RAW_FILTER, struct.pack("=II", 0x300, 0x7F0))
p.setsockopt(socket.SOL_SOCKET, SO_TIMESTAMPNS, 1)
p.setblocking(False)
t = (time.clock_gettime_ns(time.CLOCK_REALTIME) // 10**6 + 20) * 10**6
pid = os.fork()
if pid == 0:
    said = ["child_domain %d" % p.getsockopt(socket.SOL_SOCKET, SO_DOMAIN),
            "child_options %d %d %d" % (p.getsockopt(SOL_CAN_RAW, CAN_RAW_RECV_OWN_MSGS),
                                        p.getsockopt(SOL_CAN_RAW, CAN_RAW_LOOPBACK),
                                        p.getsockopt(socket.SOL_SOCKET, SO_TIMESTAMPNS)),
            "child_nonblocking %d" % (not p.getblocking()),
            "child_bound %r" % (p.getsockname(),)]
    try:
        p.send(frame(0x301, b"early"))
        said.append("child_unbound_send sent")
    except OSError as e:
        said.append("child_unbound_send " + errno.errorcode[e.errno])
    p.bind(("can0",))
    p.setsockopt(socket.SOL_SOCKET, SO_TIMESTAMPNS, 1)
    p.setblocking(True)
    raw, cmsgs, _, _ = p.recvmsg(16, 64)
    s, ns = struct.unpack("=qq", stamps(cmsgs, SO_TIMESTAMPNS)[0])
    said.append("child_got %s %s %d" % (hex(unframe(raw)[0]), unframe(raw)[1].decode(), s * 10**9 + ns))
    sleep_until(CLOCK_REALTIME, t + 10**7)
    p.send(frame(0x301, b"kid"))
    print("\\n".join(said), flush=True)
    os._exit(0)
sleep_until(CLOCK_REALTIME, t)
p.send(frame(0x200, b"mum"))
got = []
while select.select([p], [], [], 0.05)[0]:
    raw, cmsgs, _, _ = p.recvmsg(16, 64)
    s, ns = struct.unpack("=qq", stamps(cmsgs, SO_TIMESTAMPNS)[0])
    got.append("%s %s %d" % (hex(unframe(raw)[0]), unframe(raw)[1].decode(), s * 10**9 + ns))
os.waitpid(pid, 0)
out("t", t)
out("parent_got", *got)
"""


def test_a_forked_childs_can_socket_is_opened_again_unbound_with_the_defaults_and_works():
    """The contract's own words (docs/DESIGN.md §9): a forked child's CAN fds
    are opened again, unbound and with the default options. So the child's
    fd is a CAN socket (SO_DOMAIN AF_CAN), its options the defaults
    (own messages off, loopback on, no stamps) though the parent set them,
    O_NONBLOCK kept (a file status flag, which fork shares), unbound (its
    name is no interface; a send without an address fails with ENXIO, as
    raw_sendmsg's on ifindex 0); bound, it hears the parent's frame and the
    parent hears its, each when its last bit has crossed the bus; the
    parent's socket keeps its binding, filter and options."""
    r = run_program(FORK)
    v = lines(r)
    t = int(v["t"][0])
    mum = t + standard_frame_bits(0x200, b"mum") * BIT_NS
    kid = t + 10**7 + standard_frame_bits(0x301, b"kid") * BIT_NS
    check(v.get("child_domain") == ["29"], "the child's fd is an AF_CAN socket", r)
    check(v["child_options"] == ["0", "1", "0"], "with the default options: %s" % v["child_options"], r)
    check(v["child_nonblocking"] == ["1"], "O_NONBLOCK kept", r)
    check(v["child_bound"] == ["('',)"] and v["child_unbound_send"] == ["ENXIO"],
          "unbound: no interface, a send fails with ENXIO: %s %s" % (v["child_bound"], v["child_unbound_send"]), r)
    check(v["child_got"] == ["0x200", "mum", str(mum)],
          "the child hears the parent's frame at its last bit (%d): %s" % (mum, v["child_got"]), r)
    check(v["parent_got"] == ["0x301", "kid", str(kid)],
          "the parent (filter 0x300/0x7F0: not its own 0x200) hears the child's at its last bit (%d): %s" %
          (kid, v["parent_got"]), r)


BLOCKING_READER = """\
s = sock()
s.setsockopt(socket.SOL_SOCKET, SO_TIMESTAMPNS, 1)
raw, cmsgs, _, _ = s.recvmsg(16, 64)   # blocks: nothing is on the bus yet
sec, ns = struct.unpack("=qq", stamps(cmsgs, SO_TIMESTAMPNS)[0])
out("read", hex(unframe(raw)[0]), unframe(raw)[1].hex(), sec * 10**9 + ns, time.clock_gettime_ns(time.CLOCK_REALTIME))
"""

LATE_SENDER = """\
s = sock()
sleep_until(CLOCK_REALTIME, int(sys.argv[1]))
s.send(frame(0x321, b"\\x07"))
"""


def test_a_blocking_read_wakes_for_another_programs_frame():
    """recvmsg on a CAN socket with nothing on the bus blocks, and another
    program's frame, sent after the read began, ends it when its last bit
    has crossed the bus: the stamp, and the reader's clock after the read.
    (It waited for ever: the read's wake-up was fixed when it began.)"""
    sent = EPOCH * 10**9 + 100 * 10**6
    with scenario_file(BUS) as world, scenario_file(PRELUDE + BLOCKING_READER) as reader, \
            scenario_file(PRELUDE + LATE_SENDER) as sender:
        r = tcs("-q", "-m", "lockstep", "--no-slack", "--epoch", str(EPOCH), "-w", world, "--", "sh", "-c",
                "python3 %s & python3 %s %d; wait" % (reader, sender, sent), timeout=60)
    check(r.returncode == 0, "both programs end", r)
    end = sent + standard_frame_bits(0x321, b"\x07") * BIT_NS
    check(lines(r).get("read") == ["0x321", "07", str(end), str(end)],
          "the frame read when its last bit crossed the bus, %d: %s" % (end, lines(r).get("read")), r)


if __name__ == "__main__":
    main(globals())
