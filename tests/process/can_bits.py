"""CAN frames' lengths on the wire, in bits, from ISO 11898-1 and nothing
of tcs's: classic data and remote frames (standard or extended id) and CAN
FD frames with a bit rate switch, each from its fields, its CRC and the
stuff bit after every five equal bits, then the fixed tail. A test
multiplies them by the bit time to get when a frame's last bit has crossed
the bus."""


def crc15(bits):
    crc = 0
    for b in bits:
        top = b ^ ((crc >> 14) & 1)
        crc = (crc << 1) & 0x7FFF
        if top:
            crc ^= 0x4599
    return crc


def bits_of(value, width):
    return [(value >> (width - 1 - i)) & 1 for i in range(width)]


def stuff_bits(bits, split=0, final_counts=True):
    """The stuff bits a run of bits needs (one after every five equal bits,
    the stuff bit itself, the complement, starting the next five), and how
    many of them follow bit split or a later one. final_counts: whether
    five equal bits that end the run add one (classic frames: yes; FD:
    the CRC field's first fixed stuff bit is that one)."""
    count = after = run = 0
    last = None
    for i, b in enumerate(bits):
        run, last = (run + 1, b) if b == last else (1, b)
        if run < 5 or (i == len(bits) - 1 and not final_counts):
            continue
        count, after = count + 1, after + (i >= split)
        run, last = 1, 1 - b
    return count, after


# After the CRC sequence: CRC delimiter, ACK slot, ACK delimiter, EOF (7),
# intermission (3).
TAIL = 13


def frame_bits(can_id, data, extended=False, rtr=False):
    """A classic data or remote frame's bits on the wire (ISO 11898-1): SOF,
    the id (11 bits; or 11, SRR, IDE, 18 for an extended one), RTR, IDE and
    r0 (r1 and r0), DLC, data, CRC-15, stuffed after five equal bits up to
    the CRC's end; then the tail (13)."""
    if extended:
        bits = [0] + bits_of(can_id >> 18, 11) + [1, 1] + bits_of(can_id & 0x3FFFF, 18)
    else:
        bits = [0] + bits_of(can_id, 11)
    bits += [int(rtr), 0, 0] + bits_of(len(data), 4)
    for byte in data if not rtr else b"":
        bits += bits_of(byte, 8)
    bits += bits_of(crc15(bits), 15)
    return len(bits) + stuff_bits(bits)[0] + TAIL


def socketcan_frame_bits(can_id, data):
    """frame_bits of a SocketCAN can_id (CAN_EFF_FLAG, CAN_RTR_FLAG in its
    top bits)."""
    return frame_bits(can_id & 0x1FFFFFFF, data, extended=bool(can_id & 0x80000000), rtr=bool(can_id & 0x40000000))


FD_LENGTHS = [0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64]


def fd_frame_bits(can_id, data):
    """A CAN FD frame with BRS, standard id (ISO 11898-1:2015, ISO CRC): its
    bits at the nominal bit rate and at the data bit rate. SOF, id, RRS,
    IDE, FDF, res, BRS at the nominal rate; ESI, DLC, data (dynamically
    stuffed from SOF on), then the stuff count and CRC-17 (up to 16 bytes;
    CRC-21 beyond) with their fixed stuff bits (4 + 17 + 6, or 4 + 21 + 7),
    at the data rate; the tail at the nominal rate again. The CRC field's
    length does not depend on its value, so no CRC-17 is needed here."""
    bits = [0] + bits_of(can_id, 11) + [0, 0, 1, 0]
    brs = len(bits)
    bits += [1, 0] + bits_of(FD_LENGTHS.index(len(data)), 4)
    for byte in data:
        bits += bits_of(byte, 8)
    stuff, after_brs = stuff_bits(bits, brs, final_counts=False)
    crc_field = 4 + 17 + 6 if len(data) <= 16 else 4 + 21 + 7
    return brs + 1 + stuff - after_brs + TAIL, len(bits) - brs - 1 + after_brs + crc_field


def standard_frame_bits(can_id, data):
    """A standard (11-bit id) data frame's bits."""
    return frame_bits(can_id, data)
