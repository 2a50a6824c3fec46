// What /dev/i2c-N (Linux's drivers/i2c/i2c-dev.c) checks and does before
// and after the bus, for ioctl I2C_SLAVE/I2C_SLAVE_FORCE, ioctl I2C_RDWR
// and plain read()/write(): the same errors for the same arguments.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "i2c_bus.h"

namespace tcs {

// I2C_SLAVE and I2C_SLAVE_FORCE: 0, or -EINVAL for an address over 0x7F
// (over 0x3FF after I2C_TENBIT). No kernel driver holds an address here,
// so I2C_SLAVE never returns -EBUSY.
int i2c_slave_check(unsigned long addr, bool ten_bit);

// I2C_RDWR with the caller's messages, each data holding the len bytes of
// its buffer (a read's too: with I2C_M_RECV_LEN its first byte counts).
// -EINVAL, before the bus, for no message or more than
// I2C_RDWR_IOCTL_MAX_MSGS (42), a message over 8192 bytes, or an
// I2C_M_RECV_LEN one that is no read, whose first byte is 0 or whose
// buffer cannot hold it plus 32. Then the transfer: on success (error 0,
// done = the ioctl's return, the number of messages) each read's data is
// what goes back into its buffer; on failure nothing goes back.
I2cResult i2c_rdwr(I2cBus &bus, std::vector<I2cMessage> &msgs);

// read(): one read message of count bytes (at most 8192: i2c-dev cuts a
// larger count) from the I2C_SLAVE address; on success out holds them and
// read() returns out.size().
I2cResult i2c_dev_read(I2cBus &bus, uint16_t addr, bool ten_bit, size_t count, std::vector<uint8_t> &out);
// write(): one write message of the first (at most 8192) bytes; on success
// write() returns that many.
I2cResult i2c_dev_write(I2cBus &bus, uint16_t addr, bool ten_bit, const std::vector<uint8_t> &bytes);

} // namespace tcs
