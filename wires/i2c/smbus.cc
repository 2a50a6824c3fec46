// The I2C_SMBUS ioctl over I2C messages, as Linux emulates it (see smbus.h).
#include "smbus.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string>

namespace tcs {

namespace {

// The bytes of the union a transaction of this size uses.
size_t data_size(uint32_t size)
{
	switch (size) {
	case I2C_SMBUS_BYTE:
	case I2C_SMBUS_BYTE_DATA:
		return sizeof(i2c_smbus_data::byte);
	case I2C_SMBUS_WORD_DATA:
	case I2C_SMBUS_PROC_CALL:
		return sizeof(i2c_smbus_data::word);
	default:
		return sizeof(i2c_smbus_data::block);
	}
}

// i2c-dev calls the core without the union for these two.
bool needs_no_data(uint8_t read_write, uint32_t size)
{
	return size == I2C_SMBUS_QUICK || (size == I2C_SMBUS_BYTE && read_write == I2C_SMBUS_WRITE);
}

// These send from the caller's union, so i2c-dev reads it first; the
// others start from a zeroed one.
bool sends_data(uint8_t read_write, uint32_t size)
{
	return size == I2C_SMBUS_PROC_CALL || size == I2C_SMBUS_BLOCK_PROC_CALL || size == I2C_SMBUS_I2C_BLOCK_DATA ||
	       read_write == I2C_SMBUS_WRITE;
}

SmbusResult refused(const std::string &why)
{
	SmbusResult r;
	r.xfer.error = -EINVAL;
	r.xfer.note = why;
	return r;
}

} // namespace

uint32_t i2c_funcs()
{
	return I2C_FUNC_I2C | I2C_FUNC_10BIT_ADDR | I2C_FUNC_PROTOCOL_MANGLING | I2C_FUNC_NOSTART |
	       (I2C_FUNC_SMBUS_EMUL_ALL & ~uint32_t(I2C_FUNC_SMBUS_PEC));
}

size_t i2c_smbus_data_in(uint8_t read_write, uint32_t size)
{
	if (size > I2C_SMBUS_I2C_BLOCK_DATA || read_write > I2C_SMBUS_READ || needs_no_data(read_write, size))
		return 0;
	return sends_data(read_write, size) ? data_size(size) : 0;
}

namespace {

// i2c-core's emulation: the messages for a transaction (read_write as the
// calls force it), or -EINVAL for a block too long to send.
int messages_for(uint16_t addr, uint16_t flags, uint8_t read_write, uint8_t command, uint32_t size,
		 const i2c_smbus_data &d, std::vector<I2cMessage> &msgs, std::string &why)
{
	I2cMessage w{ addr, flags, { command } };
	I2cMessage r{ addr, uint16_t(flags | I2C_M_RD), {} };
	const bool read = read_write == I2C_SMBUS_READ;
	const uint8_t n = d.block[0];
	if ((size == I2C_SMBUS_BLOCK_DATA && !read) || size == I2C_SMBUS_BLOCK_PROC_CALL ||
	    size == I2C_SMBUS_I2C_BLOCK_DATA) {
		if (n > I2C_SMBUS_BLOCK_MAX) {
			why = "I2C_SMBUS block length " + std::to_string(n) + " (at most 32)";
			return -EINVAL;
		}
	}
	switch (size) {
	case I2C_SMBUS_QUICK: // the R/W bit is the data
		w.data.clear();
		w.flags = uint16_t(flags | (read ? I2C_M_RD : 0));
		msgs = { w };
		return 0;
	case I2C_SMBUS_BYTE:
		if (read) {
			r.data.resize(1);
			msgs = { r };
		} else {
			msgs = { w };
		}
		return 0;
	case I2C_SMBUS_BYTE_DATA:
	case I2C_SMBUS_WORD_DATA: {
		const size_t len = size == I2C_SMBUS_BYTE_DATA ? 1 : 2;
		if (read) {
			r.data.resize(len);
			msgs = { w, r };
			return 0;
		}
		w.data.push_back(len == 1 ? d.byte : uint8_t(d.word & 0xFF));
		if (len == 2)
			w.data.push_back(uint8_t(d.word >> 8));
		msgs = { w };
		return 0;
	}
	case I2C_SMBUS_PROC_CALL:
		w.data.push_back(uint8_t(d.word & 0xFF));
		w.data.push_back(uint8_t(d.word >> 8));
		r.data.resize(2);
		msgs = { w, r };
		return 0;
	case I2C_SMBUS_BLOCK_DATA:
	case I2C_SMBUS_BLOCK_PROC_CALL:
		// The count byte, then the block; a read takes the count first.
		r.flags |= I2C_M_RECV_LEN;
		r.data.resize(1);
		if (size == I2C_SMBUS_BLOCK_DATA && read) {
			msgs = { w, r };
			return 0;
		}
		w.data.insert(w.data.end(), d.block, d.block + n + 1);
		msgs = size == I2C_SMBUS_BLOCK_DATA ? std::vector<I2cMessage>{ w } : std::vector<I2cMessage>{ w, r };
		return 0;
	default: // I2C_SMBUS_I2C_BLOCK_DATA: no count byte on the wire
		if (read) {
			r.data.resize(n);
			msgs = { w, r };
		} else {
			w.data.insert(w.data.end(), d.block + 1, d.block + 1 + n);
			msgs = { w };
		}
		return 0;
	}
}

// The emulation's result in the union; 0 or -EPROTO.
int read_back(uint32_t size, const std::vector<I2cMessage> &msgs, i2c_smbus_data &d, std::string &why)
{
	switch (size) {
	case I2C_SMBUS_BYTE:
		d.byte = msgs[0].data[0];
		return 0;
	case I2C_SMBUS_BYTE_DATA:
		d.byte = msgs[1].data[0];
		return 0;
	case I2C_SMBUS_WORD_DATA:
	case I2C_SMBUS_PROC_CALL:
		d.word = uint16_t(msgs[1].data[0] | msgs[1].data[1] << 8);
		return 0;
	case I2C_SMBUS_I2C_BLOCK_DATA:
		std::copy_n(msgs[1].data.begin(), d.block[0], d.block + 1);
		return 0;
	default: { // the block calls: count and block
		const uint8_t count = msgs[1].data[0];
		if (count > I2C_SMBUS_BLOCK_MAX || msgs[1].data.size() < size_t(count) + 1) {
			why = "block count " + std::to_string(count) + " from the chip (at most 32)";
			return -EPROTO;
		}
		memcpy(d.block, msgs[1].data.data(), size_t(count) + 1);
		return 0;
	}
	}
}

} // namespace

SmbusResult i2c_smbus(I2cBus &bus, uint16_t addr, bool ten_bit, uint8_t read_write, uint8_t command, uint32_t size,
		      i2c_smbus_data *data)
{
	if (size > I2C_SMBUS_I2C_BLOCK_DATA)
		return refused("I2C_SMBUS size " + std::to_string(size) + " is none of <linux/i2c.h>'s (0 to 8)");
	if (read_write != I2C_SMBUS_READ && read_write != I2C_SMBUS_WRITE)
		return refused("I2C_SMBUS read_write " + std::to_string(read_write) + " (0 or 1)");
	const bool with_data = !needs_no_data(read_write, size);
	if (with_data && !data)
		return refused("I2C_SMBUS without data");
	i2c_smbus_data temp;
	memset(&temp, 0, sizeof temp);
	const size_t datasize = data_size(size);
	if (with_data && sends_data(read_write, size))
		memcpy(&temp, data, datasize);
	uint32_t as = size;
	if (size == I2C_SMBUS_I2C_BLOCK_BROKEN) {
		// The old I2C block call: the new one, reading a whole 32.
		as = I2C_SMBUS_I2C_BLOCK_DATA;
		if (read_write == I2C_SMBUS_READ)
			temp.block[0] = I2C_SMBUS_BLOCK_MAX;
	}
	SmbusResult r;
	const uint8_t rw = as == I2C_SMBUS_PROC_CALL || as == I2C_SMBUS_BLOCK_PROC_CALL ? I2C_SMBUS_READ : read_write;
	const int err = messages_for(addr, ten_bit ? I2C_M_TEN : 0, rw, command, as, temp, r.messages, r.xfer.note);
	if (err) {
		r.messages.clear();
		r.xfer.error = err;
		return r;
	}
	r.xfer = bus.transfer(r.messages);
	if (r.xfer.error)
		return r;
	if (r.xfer.done != r.messages.size()) {
		r.xfer.error = -EIO;
		return r;
	}
	if (rw == I2C_SMBUS_READ && as != I2C_SMBUS_QUICK) {
		r.xfer.error = read_back(as, r.messages, temp, r.xfer.note);
		if (r.xfer.error)
			return r;
	}
	// i2c-dev copies the union back after the calls and any read.
	const bool copy_back =
		as == I2C_SMBUS_PROC_CALL || as == I2C_SMBUS_BLOCK_PROC_CALL || read_write == I2C_SMBUS_READ;
	if (with_data && copy_back) {
		memcpy(data, &temp, datasize);
		r.data_out = datasize;
	}
	return r;
}

} // namespace tcs
