// The I2C_SMBUS ioctl of /dev/i2c-N as Linux carries it out on an adapter
// with no SMBus of its own: i2c-dev's checks (drivers/i2c/i2c-dev.c), then
// i2c-core's emulation (i2c_smbus_xfer_emulated, drivers/i2c/
// i2c-core-smbus.c) turning the transaction into one or two I2C messages
// run as one transfer, and the result written back into the caller's
// union i2c_smbus_data. PEC is not supported: i2c_funcs() does not report
// I2C_FUNC_SMBUS_PEC, and a transaction goes without a PEC byte whatever
// ioctl I2C_PEC said.
#pragma once

#include <linux/i2c.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "i2c_bus.h"

namespace tcs {

// I2C_FUNCS' answer for the emulated bus: that of Linux's bit-banging
// adapter (i2c-algo-bit: plain I2C, 10-bit addresses, I2C_M_NOSTART and
// the protocol manglings, every SMBus transaction emulated including block
// reads) less I2C_FUNC_SMBUS_PEC.
uint32_t i2c_funcs();

struct SmbusResult {
	// error: the ioctl's return (0 or a negative errno); bits and wire_ns:
	// the transfer's, 0 when the arguments were refused before it.
	I2cResult xfer;
	// The messages put on the bus (none when refused before).
	std::vector<I2cMessage> messages;
	// How many bytes of the caller's union the ioctl writes back (0, 1, 2
	// or 34), now in *data.
	size_t data_out = 0;
};

// How many bytes of the caller's union the ioctl reads (0 when it reads
// none) for these arguments: what to copy into *data before the call.
size_t i2c_smbus_data_in(uint8_t read_write, uint32_t size);

// ioctl(I2C_SMBUS) at address addr (I2C_SLAVE's; ten_bit after
// I2C_TENBIT) with struct i2c_smbus_ioctl_data's read_write, command, size
// and data (nullptr for a null pointer). -EINVAL for a size none of
// <linux/i2c.h>'s, a read_write neither I2C_SMBUS_READ nor
// I2C_SMBUS_WRITE, no data where the size needs it, or a block length over
// 32 to send (I2C_SMBUS_I2C_BLOCK_DATA: either way); then the transfer's
// errors (-ENXIO no chip, -EIO a NACKed byte, -EPROTO a block count from
// the chip that is 0 or over 32).
SmbusResult i2c_smbus(I2cBus &bus, uint16_t addr, bool ten_bit, uint8_t read_write, uint8_t command, uint32_t size,
		      i2c_smbus_data *data);

} // namespace tcs
