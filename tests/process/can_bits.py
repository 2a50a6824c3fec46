"""A classic CAN data frame's length on the wire, in bits, from ISO 11898-1
and nothing of tcs's: the frame's fields, its CRC-15, the stuff bit after
every five equal bits from the start of frame to the CRC's end, then the
fixed tail. A test multiplies it by the bit time to get when the frame's
last bit has crossed the bus."""

# CRC-15/CAN: x^15 + x^14 + x^10 + x^8 + x^7 + x^4 + x^3 + 1.
POLY = 0x4599
# After the CRC, never stuffed: CRC delimiter 1, ACK slot 1, ACK
# delimiter 1, end of frame 7, intermission 3.
TAIL = 13


def msb_first(value, width):
    return [(value >> (width - 1 - i)) & 1 for i in range(width)]


def crc15(bits):
    reg = 0
    for bit in bits:
        feedback = bit ^ (reg >> 14)
        reg = (reg << 1) & 0x7FFF
        if feedback:
            reg ^= POLY
    return reg


def stuff_count(bits):
    """Stuff bits a transmitter inserts: one after each run of five equal
    bits, the stuff bit itself starting the next run."""
    count, run, level = 0, 0, None
    for bit in bits:
        if bit == level:
            run += 1
        else:
            level, run = bit, 1
        if run == 5:
            count += 1
            level, run = 1 - bit, 1
    return count


def standard_frame_bits(can_id, data):
    """A standard (11-bit id) data frame: SOF, id, RTR, IDE, r0, DLC, data,
    CRC-15 (stuffed), then the tail."""
    head = [0] + msb_first(can_id, 11) + [0, 0, 0] + msb_first(len(data), 4)
    for byte in data:
        head += msb_first(byte, 8)
    body = head + msb_first(crc15(head), 15)
    return len(body) + stuff_count(body) + TAIL
