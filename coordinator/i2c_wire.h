// An I2C bus as the coordinator drives it (docs/DESIGN.md §9): each
// transfer a controller asks for (I2C_RDWR, I2C_SMBUS, read, write) runs on
// the chips at its virtual time, once the bus is free, and its answer
// reaches the controller when the transfer's last bit has: the ioctl takes
// the transfer's wire time at the bus clock. The MPU-6050s on it sample
// their link's motion at their own rate, stepped with the world.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "error.h"
#include "i2c_bus.h"
#include "mpu6050.h"
#include "scenario.h"
#include "wire_bus.h"

namespace tcs {

class I2cWire final : public WireBus {
public:
	static Result<std::unique_ptr<I2cWire>> create(const I2cSpec &spec, const std::string &scenario_file,
						       const SimWorld *world, Warn warn, uint64_t noise_key);
	int socket_type() const override;
	void opened(const std::shared_ptr<WirePort> &port) override {}
	int64_t take(WirePort &port, uint32_t type, std::string_view payload, int64_t v, const SimWorld *world) override;
	int64_t next_event() const override { return TCS_NEVER; }
	void advance(int64_t t, const SimWorld *world) override {}
	void step(int64_t s, const SimWorld &world) override;
	void trace_topics(std::vector<TraceWireTopic> &out) const override;

private:
	I2cWire(const I2cSpec &spec, Warn warn);
	int64_t transfer(WirePort &port, std::string_view payload, int64_t v);
	int64_t smbus(WirePort &port, std::string_view payload, int64_t v);
	// The answer, due when the transfer of msgs that began at v (or when
	// the bus was free) has ended.
	void answer(WirePort &port, int64_t v, const I2cResult &r, const std::vector<I2cMessage> &msgs,
		    const std::string &data);

	struct Imu {
		Mpu6050 *chip = nullptr;
		size_t pose = 0, twist = 0;    // the link's signals
		double v_before[3] = { 0, 0, 0 };
		bool have_before = false;
		int64_t next_sample = 0;
		double accel_noise = 0, gyro_noise = 0; // standard deviations
		uint64_t key = 1, drawn = 0;            // its noise stream
	};
	I2cSpec spec_;
	Warn warn_;
	I2cBus bus_;
	std::vector<Imu> imus_;
	int64_t step_ns_ = 0;
	int64_t free_at_ = 0; // the bus is busy until then
	uint64_t notes_ = 0;
};

} // namespace tcs
