// i2c-dev's argument rules around a bus transfer (see i2c_dev.h).
#include "i2c_dev.h"

#include <linux/i2c-dev.h>

#include <algorithm>
#include <cerrno>
#include <string>

namespace tcs {

namespace {

// i2c-dev's "sane amount" for one message, and for one read() or write().
constexpr size_t kMaxLen = 8192;

I2cResult refused(const std::string &why)
{
	I2cResult r;
	r.error = -EINVAL;
	r.note = why;
	return r;
}

// The bytes of one plain read() or write(): what the transfer made of them.
I2cResult one_message(I2cBus &bus, I2cMessage m, std::vector<uint8_t> *out)
{
	std::vector<I2cMessage> msgs{ std::move(m) };
	I2cResult r = bus.transfer(msgs);
	if (out && r.error == 0)
		*out = std::move(msgs[0].data);
	return r;
}

} // namespace

int i2c_slave_check(unsigned long addr, bool ten_bit)
{
	return addr > (ten_bit ? 0x3FFul : 0x7Ful) ? -EINVAL : 0;
}

I2cResult i2c_rdwr(I2cBus &bus, std::vector<I2cMessage> &msgs)
{
	if (msgs.empty() || msgs.size() > I2C_RDWR_IOCTL_MAX_MSGS)
		return refused("I2C_RDWR with " + std::to_string(msgs.size()) + " messages (1 to 42)");
	for (size_t i = 0; i < msgs.size(); i++) {
		I2cMessage &m = msgs[i];
		if (m.data.size() > kMaxLen)
			return refused("I2C_RDWR message " + std::to_string(i) + " of " +
				       std::to_string(m.data.size()) + " bytes (at most 8192)");
		if (!(m.flags & I2C_M_RECV_LEN))
			continue;
		// The buffer's first byte says how many bytes come besides the
		// block (1, or 2 with a PEC); it must hold those and 32 more.
		if (!(m.flags & I2C_M_RD) || m.data.empty() || m.data[0] < 1 ||
		    m.data.size() < m.data[0] + size_t(I2C_SMBUS_BLOCK_MAX))
			return refused("I2C_RDWR message " + std::to_string(i) +
				       ": I2C_M_RECV_LEN needs a read whose buffer's first byte n is 1 or more and "
				       "which holds n + 32 bytes");
		m.data.resize(m.data[0]);
	}
	return bus.transfer(msgs);
}

I2cResult i2c_dev_read(I2cBus &bus, uint16_t addr, bool ten_bit, size_t count, std::vector<uint8_t> &out)
{
	I2cMessage m;
	m.addr = addr;
	m.flags = uint16_t(I2C_M_RD | (ten_bit ? I2C_M_TEN : 0));
	m.data.assign(std::min(count, kMaxLen), 0);
	return one_message(bus, std::move(m), &out);
}

I2cResult i2c_dev_write(I2cBus &bus, uint16_t addr, bool ten_bit, const std::vector<uint8_t> &bytes)
{
	I2cMessage m;
	m.addr = addr;
	m.flags = ten_bit ? I2C_M_TEN : 0;
	m.data.assign(bytes.begin(), bytes.begin() + std::min(bytes.size(), kMaxLen));
	return one_message(bus, std::move(m), nullptr);
}

} // namespace tcs
