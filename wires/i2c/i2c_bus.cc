// I2cBus: a combined transfer on the wire, bit by bit (see i2c_bus.h).
#include "i2c_bus.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdio>

namespace tcs {

namespace {

// The transfer under way: the bits it has taken and the chips it addressed
// (each told of the STOP).
struct Wire {
	int64_t bits = 0;
	std::vector<I2cChip *> addressed;

	void start(I2cChip *chip, bool read)
	{
		chip->start(read);
		if (std::find(addressed.begin(), addressed.end(), chip) == addressed.end())
			addressed.push_back(chip);
	}
	void stop()
	{
		bits += 1;
		for (I2cChip *c : addressed)
			c->stop();
		addressed.clear();
	}
};

std::string hex(unsigned v)
{
	char buf[16];
	snprintf(buf, sizeof buf, "0x%02x", v);
	return buf;
}

// Message i's address and R/W bit: the chip that ACKed it (nullptr if none
// did), 0 or the error of a NACK.
int send_address(const std::map<uint32_t, std::unique_ptr<I2cChip>> &chips, const I2cMessage &m, size_t i,
		 Wire &w, I2cChip *&chip, std::string &note)
{
	const bool read = m.flags & I2C_M_RD;
	chip = nullptr;
	if (m.flags & I2C_M_TEN) {
		// With I2C_M_IGNORE_NAK the master sends every address byte
		// whatever answered the first.
		const bool go_on = m.flags & I2C_M_IGNORE_NAK;
		const uint32_t a = m.addr & 0x3FF;
		const std::string none =
			"message " + std::to_string(i) + ": no chip at 10-bit address " + hex(a) + " (NACK)";
		// 11110 A9 A8 W: ACKed by every 10-bit chip whose A9 A8 are those.
		w.bits += 9;
		const uint32_t high = 0x10000 | (a & 0x300);
		const auto first = chips.lower_bound(high);
		if ((first == chips.end() || first->first >= high + 0x100) && !go_on) {
			note = none;
			return -ENXIO;
		}
		w.bits += 9; // A7..A0
		const auto it = chips.find(0x10000 | a);
		chip = it == chips.end() ? nullptr : it->second.get();
		if (chip)
			w.start(chip, false);
		if (read) {
			w.bits += 1 + 9; // Sr, 11110 A9 A8 R
			if (chip)
				w.start(chip, true);
		}
		if (!chip)
			note = none;
		return chip ? 0 : -ENXIO;
	}
	const uint32_t a = m.addr & 0x7F;
	w.bits += 9;
	const auto it = chips.find(a);
	if (it == chips.end()) {
		note = "message " + std::to_string(i) + ": no chip at " + hex(a) + " (address NACKed)";
		return -ENXIO;
	}
	chip = it->second.get();
	w.start(chip, read != bool(m.flags & I2C_M_REV_DIR_ADDR));
	return 0;
}

int write_bytes(const I2cMessage &m, size_t i, I2cChip *chip, Wire &w, std::string &note)
{
	for (size_t k = 0; k < m.data.size(); k++) {
		w.bits += 9;
		const bool ack = chip && chip->write(m.data[k]);
		if (!ack && !(m.flags & I2C_M_IGNORE_NAK)) {
			note = "message " + std::to_string(i) + ": byte " + std::to_string(k) + " NACKed";
			return -EIO;
		}
	}
	return 0;
}

int read_bytes(I2cMessage &m, size_t i, I2cChip *chip, Wire &w, std::string &note)
{
	const int per_byte = m.flags & I2C_M_NO_RD_ACK ? 8 : 9;
	size_t n = m.data.size();
	for (size_t k = 0; k < n; k++) {
		const uint8_t b = chip ? chip->read() : 0xFF; // no chip: the pull-ups
		w.bits += per_byte;
		m.data[k] = b;
		if (k == 0 && (m.flags & I2C_M_RECV_LEN)) {
			if (b == 0 || b > I2C_SMBUS_BLOCK_MAX) {
				note = "message " + std::to_string(i) + ": block count " + std::to_string(b) +
				       " is not 1 to 32";
				return -EPROTO;
			}
			n += b;
			m.data.resize(n);
		}
	}
	return 0;
}

} // namespace

int64_t i2c_bits_ns(int64_t bits, int64_t clock_hz)
{
	if (bits <= 0 || clock_hz <= 0)
		return 0;
	const __int128 ns = ((__int128)bits * 1000000000 + clock_hz / 2) / clock_hz;
	return ns > INT64_MAX ? INT64_MAX : (int64_t)ns;
}

I2cBus::I2cBus(int64_t clock_hz) : clock_hz_(clock_hz > 0 ? clock_hz : 100000) {}

uint32_t I2cBus::key(uint16_t addr, bool ten_bit)
{
	return ten_bit ? 0x10000u | addr : addr;
}

Status I2cBus::attach(uint16_t addr, std::unique_ptr<I2cChip> chip, bool ten_bit)
{
	if (!chip)
		return Error{ "no chip to attach at " + hex(addr) };
	if (addr > (ten_bit ? 0x3FF : 0x7F))
		return Error{ "I2C address " + hex(addr) + " is not a " + (ten_bit ? "10" : "7") + "-bit address" };
	auto [it, added] = chips_.try_emplace(key(addr, ten_bit), std::move(chip));
	if (!added)
		return Error{ "I2C address " + hex(addr) + " already has a chip" };
	return Ok{};
}

I2cChip *I2cBus::chip(uint16_t addr, bool ten_bit) const
{
	const auto it = chips_.find(key(addr, ten_bit));
	return it == chips_.end() ? nullptr : it->second.get();
}

I2cResult I2cBus::transfer(std::vector<I2cMessage> &msgs)
{
	I2cResult r;
	Wire w;
	w.bits = 1; // START
	I2cChip *chip = nullptr;
	for (size_t i = 0; i < msgs.size(); i++) {
		I2cMessage &m = msgs[i];
		if (!(m.flags & I2C_M_NOSTART)) {
			if (i > 0 && (msgs[i - 1].flags & I2C_M_STOP))
				w.stop();
			if (i > 0)
				w.bits += 1; // a repeated START, or the START after that STOP
			std::string why;
			const int err = send_address(chips_, m, i, w, chip, why);
			if (err && !(m.flags & I2C_M_IGNORE_NAK)) {
				r.error = err;
				r.note = why;
				break;
			}
		}
		const int err =
			m.flags & I2C_M_RD ? read_bytes(m, i, chip, w, r.note) : write_bytes(m, i, chip, w, r.note);
		if (err) {
			r.error = err;
			break;
		}
		r.done++;
	}
	w.stop();
	r.bits = w.bits;
	r.wire_ns = i2c_bits_ns(r.bits, clock_hz_);
	return r;
}

} // namespace tcs
