// The fuzz target for the I2C wire (wires/i2c/): an input is what a
// controller asks of /dev/i2c-N, one operation after another, on a bus
// with an MPU-6050 at 0x68 and nothing at 0x69 (nor at 10-bit 0x068):
// I2C_SMBUS argument blocks (any read_write, command, size and union, or a
// null data pointer), I2C_RDWR message lists (any addresses, flags and
// lengths, a few past i2c-dev's limits), plain read()/write(), and samples
// of any doubles. Promised: only the documented errnos; nothing sent when
// the arguments are refused; bits and lengths within what the messages
// allow; the union written back only as far as data_out says; the chip's
// read-only and self-clearing registers as the register map has them.
//
// The first byte picks the bus clock; then each operation is a byte
// (its kind) and its fields, bytes past the end reading as zeros.
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <memory>
#include <string>
#include <vector>

#include "fuzz_target.h"
#include "i2c_dev.h"
#include "mpu6050.h"
#include "smbus.h"

namespace {

using tcs::I2cMessage;
using tcs_fuzz::check;

constexpr int64_t kClocks[4] = { 100000, 400000, 1, 3400000 };
constexpr size_t kMaxOps = 64;
enum Op { kSmbus, kRdwr, kSample, kPlain, kOps };

// The input, read field by field; zeros past its end.
struct Reader {
	const uint8_t *p;
	size_t n, at = 0;
	uint64_t le(int bytes)
	{
		uint64_t v = 0;
		for (int i = 0; i < bytes; i++, at++)
			v |= uint64_t(at < n ? p[at] : 0) << (8 * i);
		return v;
	}
	uint8_t byte() { return uint8_t(le(1)); }
	bool done() const { return at >= n; }
};

struct Address {
	uint16_t addr;
	bool ten_bit;
};

// The chip, the empty 7-bit and 10-bit addresses, or another.
Address address(uint8_t b)
{
	switch (b & 3) {
	case 0:
		return { 0x68, false };
	case 1:
		return { 0x69, false };
	case 2:
		return { 0x68, true };
	default:
		return { uint16_t(b << 3 | 0x68 >> 4), bool(b & 4) };
	}
}

// The most bits messages of these lengths can take: a START, then each
// a repeated START (or STOP and START), a 10-bit read's address, and its
// bytes with a RECV_LEN block's 32 more; a STOP.
int64_t max_bits(const std::vector<I2cMessage> &msgs)
{
	int64_t bits = 2;
	for (const I2cMessage &m : msgs)
		bits += 2 + 28 + 9 * (int64_t(m.data.size()) + 32);
	return bits;
}

bool one_of(int e, std::initializer_list<int> errs)
{
	for (int x : errs)
		if (e == x)
			return true;
	return false;
}

// What the register map says holds whatever a controller does.
void check_chip(const tcs::Mpu6050 &imu)
{
	check(imu.peek(0x75) == 0x68);
	check((imu.peek(0x6B) & 0x80) == 0);
	check((imu.peek(0x6A) & 0x07) == 0);
	check(imu.peek(0x72) == 0 && imu.peek(0x73) == 0 && imu.peek(0x74) == 0);
	check((imu.peek(0x3A) & ~1) == 0);
	for (int reg = 0x49; reg <= 0x60; reg++)
		check(imu.peek(uint8_t(reg)) == 0);
	const int64_t period = imu.sample_period_ns();
	check(period >= 125000 && period <= 256 * 1000000);
}

void smbus(Reader &in, tcs::I2cBus &bus)
{
	const uint8_t rw = in.byte(), command = in.byte(), sz = in.byte();
	const uint32_t size = sz < 16 ? sz : uint32_t(in.le(4));
	const Address a = address(in.byte());
	const bool null_data = in.byte() & 1;
	i2c_smbus_data data, before;
	for (size_t i = 0; i < sizeof data.block; i++)
		data.block[i] = in.byte();
	before = data;
	const tcs::SmbusResult r =
		tcs::i2c_smbus(bus, a.addr, a.ten_bit, rw, command, size, null_data ? nullptr : &data);
	// The chip ACKs every byte: a NACK is an address's.
	check(one_of(r.xfer.error, { 0, -EINVAL, -ENXIO, -EPROTO }));
	check(r.xfer.error == 0 || !r.xfer.note.empty());
	check(r.data_out == 0 || r.data_out == 1 || r.data_out == 2 || r.data_out == 34);
	check(r.xfer.error == 0 || r.data_out == 0);
	check(memcmp(data.block + r.data_out, before.block + r.data_out, sizeof data.block - r.data_out) == 0);
	if (r.data_out == 34 && (size == I2C_SMBUS_BLOCK_DATA || size == I2C_SMBUS_BLOCK_PROC_CALL))
		check(data.block[0] >= 1 && data.block[0] <= 32);
	if (r.xfer.error == -EINVAL) {
		check(r.messages.empty() && r.xfer.bits == 0);
		return;
	}
	check(size <= I2C_SMBUS_I2C_BLOCK_DATA && rw <= 1);
	check(r.messages.size() == 1 || r.messages.size() == 2);
	for (const I2cMessage &m : r.messages)
		check(m.data.size() <= 34);
	check(r.xfer.bits >= 11 && r.xfer.bits <= max_bits(r.messages));
	check(r.xfer.wire_ns == tcs::i2c_bits_ns(r.xfer.bits, bus.clock_hz()));
}

void rdwr(Reader &in, tcs::I2cBus &bus)
{
	std::vector<I2cMessage> msgs(in.byte() % 48);
	std::vector<size_t> asked;
	for (I2cMessage &m : msgs) {
		const uint8_t sel = in.byte();
		m.addr = sel & 0x80 ? uint16_t(in.le(2)) : address(sel).addr;
		m.flags = uint16_t(in.le(2));
		if (!(sel & 0x80) && address(sel).ten_bit)
			m.flags |= I2C_M_TEN;
		const uint8_t lb = in.byte();
		const size_t len = lb == 255 ? 8193 : lb == 254 ? 8192 : lb % 48;
		m.data.resize(len);
		// A write's bytes; a read's first (RECV_LEN's count of extra
		// bytes), always in the input.
		if (m.flags & I2C_M_RD) {
			const uint8_t first = in.byte();
			if (len)
				m.data[0] = first;
		} else {
			for (size_t k = 0; k < len; k++)
				m.data[k] = in.byte();
		}
		asked.push_back(len);
	}
	const tcs::I2cResult r = tcs::i2c_rdwr(bus, msgs);
	check(one_of(r.error, { 0, -EINVAL, -ENXIO, -EIO, -EPROTO }));
	check(r.error == 0 || !r.note.empty());
	if (r.error == -EINVAL) {
		check(r.bits == 0 && r.done == 0);
		return;
	}
	check(!msgs.empty() && msgs.size() <= 42);
	check(r.done <= msgs.size() && (r.error != 0 || r.done == msgs.size()));
	check(r.bits >= 2 && r.bits <= max_bits(msgs));
	check(r.wire_ns == tcs::i2c_bits_ns(r.bits, bus.clock_hz()));
	if (r.error)
		return;
	for (size_t i = 0; i < msgs.size(); i++) {
		const I2cMessage &m = msgs[i];
		check(asked[i] <= 8192);
		if (m.flags & I2C_M_RECV_LEN) // its extra bytes, the count and the block
			check(m.data.size() >= 2 && m.data.size() <= asked[i] && m.data[0] >= 1 && m.data[0] <= 32);
		else
			check(m.data.size() == asked[i]);
	}
}

void sample(Reader &in, tcs::Mpu6050 &imu)
{
	tcs::ImuReading s;
	double *fields[7] = { &s.accel[0], &s.accel[1], &s.accel[2], &s.gyro[0], &s.gyro[1], &s.gyro[2], &s.temp_c };
	for (double *f : fields) {
		const uint64_t bits = in.le(8);
		memcpy(f, &bits, sizeof bits);
	}
	uint8_t data[14];
	for (int i = 0; i < 14; i++)
		data[i] = imu.peek(uint8_t(0x3B + i));
	const bool sampling = imu.sampling();
	imu.sample(s);
	if (!sampling)
		for (int i = 0; i < 14; i++)
			check(imu.peek(uint8_t(0x3B + i)) == data[i]);
}

void plain(Reader &in, tcs::I2cBus &bus)
{
	const bool read = in.byte() & 1;
	const Address a = address(in.byte());
	const size_t count = in.byte();
	std::vector<uint8_t> bytes;
	tcs::I2cResult r;
	if (read) {
		r = tcs::i2c_dev_read(bus, a.addr, a.ten_bit, count, bytes);
		check(r.error != 0 || bytes.size() == count);
	} else {
		for (size_t k = 0; k < count; k++)
			bytes.push_back(in.byte());
		r = tcs::i2c_dev_write(bus, a.addr, a.ten_bit, bytes);
	}
	// The chip is at 0x68 alone; no address here reaches it but that one.
	check(one_of(r.error, { 0, -ENXIO }));
	check(r.bits == (r.error ? 1 + 9 + 1 : 1 + 9 + 9 * int64_t(count) + 1));
}

// ---- Seeds ----

std::string le(uint64_t v, int bytes)
{
	std::string s(size_t(bytes), '\0');
	tcs_fuzz::put_le(s, 0, v, bytes);
	return s;
}

std::string smbus_op(uint8_t rw, uint8_t command, uint8_t size, uint8_t addr_sel, std::string block = "")
{
	block.resize(34, '\0');
	return std::string{ char(kSmbus), char(rw), char(command), char(size), char(addr_sel), '\0' } + block;
}

// A message: addr selector, flags, length byte, bytes (a read: its first).
std::string msg(uint8_t sel, uint16_t flags, uint8_t len_byte, const std::string &bytes)
{
	return std::string(1, char(sel)) + le(flags, 2) + std::string(1, char(len_byte)) + bytes;
}

std::string sample_op(double ax, double ay, double az, double gx, double gy, double gz, double t)
{
	std::string s(1, char(kSample));
	for (double v : { ax, ay, az, gx, gy, gz, t }) {
		std::string f(8, '\0');
		memcpy(f.data(), &v, 8);
		s += f;
	}
	return s;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	Reader in{ data, size };
	tcs::I2cBus bus(kClocks[in.byte() & 3]);
	auto chip = std::make_unique<tcs::Mpu6050>();
	tcs::Mpu6050 &imu = *chip;
	check(bus.attach(0x68, std::move(chip)).ok());
	for (size_t ops = 0; ops < kMaxOps && !in.done(); ops++) {
		switch (in.byte() % kOps) {
		case kSmbus:
			smbus(in, bus);
			break;
		case kRdwr:
			rdwr(in, bus);
			break;
		case kSample:
			sample(in, imu);
			break;
		default:
			plain(in, bus);
			break;
		}
		check_chip(imu);
	}
	return 0;
}

const char *tcs_fuzz_name()
{
	return "i2c_fuzz";
}

std::vector<std::string> tcs_fuzz_seeds()
{
	const std::string zero(1, '\0');
	const std::string wake = smbus_op(I2C_SMBUS_WRITE, 0x6B, I2C_SMBUS_BYTE_DATA, 0, zero);
	const std::string rest = sample_op(0, 0, 9.80665, 0.1, -0.2, 0.3, 25);
	const std::string burst =
		std::string(1, char(kRdwr)) + "\x02" + msg(0, 0, 1, "\x3b") + msg(0, I2C_M_RD, 14, zero);
	return {
		std::string(1, '\0') + smbus_op(I2C_SMBUS_READ, 0x75, I2C_SMBUS_BYTE_DATA, 0),
		std::string(1, '\1') + wake + rest + burst,
		std::string(1, '\1') + wake + smbus_op(I2C_SMBUS_WRITE, 0x38, I2C_SMBUS_BYTE_DATA, 0, "\x01") + rest +
			smbus_op(I2C_SMBUS_READ, 0x3A, I2C_SMBUS_BYTE_DATA, 0),
		std::string(1, '\0') + smbus_op(I2C_SMBUS_READ, 0x3B, I2C_SMBUS_I2C_BLOCK_DATA, 0, "\x0e") +
			smbus_op(I2C_SMBUS_READ, 0x75, I2C_SMBUS_BLOCK_DATA, 0) +
			smbus_op(I2C_SMBUS_WRITE, 0x19, I2C_SMBUS_I2C_BLOCK_DATA, 0, "\x04\x07\x03\x18\x10"),
		std::string(1, '\2') + smbus_op(I2C_SMBUS_READ, 0x00, I2C_SMBUS_QUICK, 1) +
			smbus_op(I2C_SMBUS_WRITE, 0x6B, I2C_SMBUS_BLOCK_PROC_CALL, 2, "\x21") +
			smbus_op(I2C_SMBUS_READ, 0x00, I2C_SMBUS_I2C_BLOCK_BROKEN, 0),
		// SMPLRT_DIV 5 read as a block count, by I2C_RDWR and by SMBus.
		zero + smbus_op(I2C_SMBUS_WRITE, 0x19, I2C_SMBUS_BYTE_DATA, 0, "\x05") + std::string(1, char(kRdwr)) +
			"\x02" + msg(0, 0, 1, "\x19") + msg(0, I2C_M_RD | I2C_M_RECV_LEN, 40, "\x01") +
			smbus_op(I2C_SMBUS_READ, 0x19, I2C_SMBUS_BLOCK_DATA, 0) +
			smbus_op(I2C_SMBUS_WRITE, 0x19, I2C_SMBUS_BLOCK_PROC_CALL, 0, "\x01\x02"),
		std::string(1, '\3') + std::string(1, char(kRdwr)) + "\x03" + msg(1, I2C_M_IGNORE_NAK, 2, "\x01\x02") +
			msg(0, I2C_M_NOSTART | I2C_M_RD, 3, std::string(1, '\0')) + msg(2, I2C_M_STOP, 0, ""),
		std::string(1, '\0') + std::string(1, char(kRdwr)) + "\x2b" + std::string(43 * 4, '\0'),
		zero + std::string(1, char(kRdwr)) + "\x01" + msg(0, I2C_M_RD, 255, zero),
		// write 0x6B 0x80 (DEVICE_RESET) to 0x68, then read 16 bytes.
		zero + wake + std::string{ char(kPlain), 0, 0, 2, 0x6B, char(0x80), char(kPlain), 1, 0, 16 },
		std::string(1, '\1') + wake + sample_op(NAN, INFINITY, -1e300, 1e9, -0.0, 5e-324, -300) + burst,
	};
}

std::vector<std::string> tcs_fuzz_tokens()
{
	return { le(0x6B, 1), le(0x75, 1), le(0x3B, 1), le(0x74, 1), le(0x80, 1), le(I2C_M_RD, 2),
		 le(I2C_M_RD | I2C_M_RECV_LEN, 2), le(I2C_M_TEN, 2), le(I2C_M_NOSTART, 2), le(I2C_M_IGNORE_NAK, 2),
		 le(I2C_M_STOP, 2), le(I2C_M_NO_RD_ACK | I2C_M_RD, 2), le(0xFFFFFFFF, 4), std::string(1, '\x21') };
}

// An operation of a random kind, well formed, somewhere in the input.
bool tcs_fuzz_mutate(std::string &s, tcs_fuzz::Rng &rng)
{
	if (s.empty())
		return false;
	std::string op;
	switch (rng.below(3)) {
	case 0: {
		std::string block(34, '\0');
		block[0] = char(rng.below(40));
		op = smbus_op(uint8_t(rng.below(3)), uint8_t(rng.next()), uint8_t(rng.below(10)), uint8_t(rng.below(4)),
			      block);
		break;
	}
	case 1: {
		const size_t n = 1 + rng.below(4);
		op = std::string(1, char(kRdwr)) + char(n);
		for (size_t i = 0; i < n; i++) {
			const uint16_t flags = uint16_t(rng.below(2) ? rng.next() : rng.below(2));
			const uint8_t len = uint8_t(rng.below(40));
			const std::string bytes(flags & I2C_M_RD ? 1 : len, char(rng.next()));
			op += msg(uint8_t(rng.below(4)), flags, len, bytes);
		}
		break;
	}
	default: {
		double v[7];
		for (double &x : v) {
			const uint64_t bits = rng.next();
			memcpy(&x, &bits, 8);
			if (rng.below(2))
				x = double(int64_t(rng.below(80)) - 40);
		}
		op = sample_op(v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
	}
	}
	s.insert(1 + rng.below(s.size()), op);
	return true;
}
