// A chip for the I2C tests that writes down what it sees of the wire
// ("Sw" a START for a write, "Sr" for a read, "w3b" a byte written, "r" a
// byte read, "P" a STOP), answers reads from a list, and can NACK; and a
// bus with one at 0x50.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <memory>
#include <string>

#include "i2c_bus.h"

class RecordingChip : public tcs::I2cChip {
public:
	std::string log;
	std::deque<uint8_t> replies; // what reads return, in order; then 0xEE
	int ack_writes = -1;	     // bytes written it ACKs before NACKing (-1: all)

	void start(bool read) override { log += read ? "Sr " : "Sw "; }
	bool write(uint8_t byte) override
	{
		char buf[8];
		snprintf(buf, sizeof buf, "w%02x ", byte);
		log += buf;
		if (ack_writes < 0)
			return true;
		return written_++ < ack_writes;
	}
	uint8_t read() override
	{
		log += "r ";
		if (replies.empty())
			return 0xEE;
		const uint8_t b = replies.front();
		replies.pop_front();
		return b;
	}
	void stop() override { log += "P "; }

private:
	int written_ = 0;
};

// A bus at clock_hz with a RecordingChip at 0x50.
struct RecorderRig {
	explicit RecorderRig(int64_t clock_hz = 100000) : bus(clock_hz)
	{
		auto c = std::make_unique<RecordingChip>();
		chip = c.get();
		if (!bus.attach(0x50, std::move(c)).ok())
			abort();
	}
	tcs::I2cBus bus;
	RecordingChip *chip;
};
