// An I2C bus with chips at addresses, driven as Linux's bit-banging
// adapter (drivers/i2c/algos/i2c-algo-bit.c, the reference of how an
// adapter puts struct i2c_msg on the wire) drives it: a combined transfer
// is a START, each message's address and bytes with a repeated START
// between messages, and a STOP. What it costs is counted in bit times.
//
// Flags honoured (<linux/i2c.h>): I2C_M_RD; I2C_M_TEN (two address bytes,
// and for a read a repeated START and the first byte again with R/W set,
// as the I2C specification's combined format has it); I2C_M_RECV_LEN (the
// first byte read is a count of 1 to 32 more; 0 or more than 32 fails with
// -EPROTO after that byte, which the master NACKs); I2C_M_IGNORE_NAK (a NACK
// of the address or of a byte written counts as an ACK); I2C_M_NO_RD_ACK (a
// byte read takes 8 bits, no ACK bit); I2C_M_STOP (a STOP and a START
// after the message, not a repeated START); I2C_M_NOSTART (no START nor
// address: the bytes go on to the chip the previous message addressed; on
// the first message no chip is addressed, so its bytes are NACKed and read
// 0xFF, the pull-ups' level); I2C_M_REV_DIR_ADDR (a 7-bit address's R/W
// bit, which the chip is told, is inverted; the bytes still go the way
// I2C_M_RD says). With I2C_M_IGNORE_NAK a 10-bit address is sent whole
// whatever answered its first byte.
// I2C_M_DMA_SAFE means nothing here. Not modelled: i2c-algo-bit's retries
// of a NACKed address, clock stretching, arbitration.
//
// Errors are those i2c-algo-bit returns (Documentation/i2c/fault-codes.rst):
// -ENXIO when an address is NACKed ("nothing listening at that address":
// what i2c-dev's users see from ioctl and read/write), -EIO when a byte
// written is NACKed, -EPROTO for a bad RECV_LEN count. The transfer stops
// there, with its STOP.
#pragma once

#include <linux/i2c.h>

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "error.h"

namespace tcs {

// One segment of a transfer, as struct i2c_msg. A write's data is what is
// sent; a read's data has the length to read on entry and the bytes read on
// return (with I2C_M_RECV_LEN it grows by the count the chip sent).
struct I2cMessage {
	uint16_t addr = 0;
	uint16_t flags = 0;
	std::vector<uint8_t> data;
};

// What a chip sees of the wire. A chip attached to a bus ACKs its address.
class I2cChip {
public:
	virtual ~I2cChip() = default;
	// A START or repeated START with the chip's address; read: the R/W bit.
	virtual void start(bool read) = 0;
	// A byte from the master; false NACKs it.
	virtual bool write(uint8_t byte) = 0;
	// A byte to the master.
	virtual uint8_t read() = 0;
	// The STOP that ends a transfer (or an I2C_M_STOP) the chip took part in.
	virtual void stop() = 0;
};

struct I2cResult {
	int error = 0;	  // 0, or a negative errno as the adapter returns it
	size_t done = 0;  // messages carried out whole (a transfer's return value when error is 0)
	int64_t bits = 0; // bit times the bus was held, from the START to the STOP
	int64_t wire_ns = 0; // those bits at the bus clock
	std::string note; // why it failed, for the log; empty when it did not
};

// The time of `bits` bit times at clock_hz (> 0), to the nearest ns.
int64_t i2c_bits_ns(int64_t bits, int64_t clock_hz);

class I2cBus {
public:
	// clock_hz: SCL's rate (100000 standard mode, 400000 fast mode, or any);
	// one that is not positive is taken as 100 kHz.
	explicit I2cBus(int64_t clock_hz = 100000);
	int64_t clock_hz() const { return clock_hz_; }
	// A chip at a 7-bit address (0 to 0x7F) or a 10-bit one (0 to 0x3FF);
	// an error if the address is out of range or taken.
	Status attach(uint16_t addr, std::unique_ptr<I2cChip> chip, bool ten_bit = false);
	// The chip at an address, or nullptr.
	I2cChip *chip(uint16_t addr, bool ten_bit = false) const;
	// Carries out a combined transfer, as an adapter's master_xfer does:
	// any number of messages of any length (i2c-dev's limits are
	// i2c_dev.h's). An address is what fits its bits on the wire: a 7-bit
	// one's low 7, a 10-bit one's low 10.
	I2cResult transfer(std::vector<I2cMessage> &msgs);

private:
	static uint32_t key(uint16_t addr, bool ten_bit);
	int64_t clock_hz_;
	std::map<uint32_t, std::unique_ptr<I2cChip>> chips_;
};

} // namespace tcs
