// An I2C bus and its chips in virtual time (see i2c_wire.h).
#include "i2c_wire.h"

#include <linux/i2c-dev.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "i2c_dev.h"
#include "link_motion.h"
#include "sensor_models.h"
#include "smbus.h"
#include "tcs/random_stream.h"

namespace tcs {

namespace {

constexpr uint64_t kMaxNotes = 20;

} // namespace

I2cWire::I2cWire(const I2cSpec &spec, Warn warn) : spec_(spec), warn_(std::move(warn)), bus_(spec.clock_hz) {}

Result<std::unique_ptr<I2cWire>> I2cWire::create(const I2cSpec &spec, const std::string &scenario_file,
						 const SimWorld *world, Warn warn, uint64_t noise_key)
{
	std::unique_ptr<I2cWire> w(new I2cWire(spec, std::move(warn)));
	w->step_ns_ = world ? world->step_ns() : 0;
	for (const I2cDeviceSpec &d : spec.devices) {
		auto chip = std::make_unique<Mpu6050>();
		Imu imu;
		imu.chip = chip.get();
		imu.accel_noise = d.accel_noise;
		imu.gyro_noise = d.gyro_noise;
		imu.key = tcs_random_key(noise_key, 0x12c00 + (uint64_t(spec.bus) << 8) + d.address);
		if (Status s = w->bus_.attach(uint16_t(d.address), std::move(chip)); !s)
			return Error{ scenario_file + ":" + std::to_string(d.line) + ": " + s.error().message };
		if (world) {
			long pose = world->find(d.link.name + ".pose"), twist = world->find(d.link.name + ".twist");
			if (pose < 0 || twist < 0)
				return Error{ scenario_file + ":" + std::to_string(d.link.line) + ": unknown link '" +
					      d.link.name + "'" };
			imu.pose = size_t(pose), imu.twist = size_t(twist);
		}
		w->imus_.push_back(imu);
	}
	return w;
}

int I2cWire::socket_type() const
{
	return SOCK_SEQPACKET;
}

void I2cWire::step(int64_t s, const SimWorld &world)
{
	std::vector<double> values;
	for (Imu &imu : imus_) {
		values.clear();
		world.read(imu.pose, values);
		world.read(imu.twist, values);
		if (values.size() < 13)
			continue;
		LinkMotion m = link_motion(values.data(), values.data() + 7, imu.have_before ? imu.v_before : nullptr,
					   double(step_ns_) * 1e-9);
		std::copy(values.begin() + 7, values.begin() + 10, imu.v_before);
		imu.have_before = true;
		if (!imu.chip->sampling() || s < imu.next_sample)
			continue;
		ImuReading r;
		for (int i = 0; i < 3; i++) {
			r.accel[i] = m.accel[i] + (imu.accel_noise > 0 ? imu.accel_noise * gaussian_draw(imu.key, imu.drawn) : 0);
			r.gyro[i] = m.gyro[i] + (imu.gyro_noise > 0 ? imu.gyro_noise * gaussian_draw(imu.key, imu.drawn) : 0);
		}
		r.temp_c = 25;
		imu.chip->sample(r);
		imu.next_sample = s + std::max<int64_t>(imu.chip->sample_period_ns(), 1);
	}
}

void I2cWire::answer(WirePort &port, int64_t v, const I2cResult &r, const std::vector<I2cMessage> &msgs,
		     const std::string &data)
{
	const int64_t start = std::max(v, free_at_);
	free_at_ = start + r.wire_ns;
	if (trace_) {
		std::vector<TraceI2cMessage> traced;
		for (const I2cMessage &m : msgs)
			traced.push_back({ m.addr, m.flags, m.data });
		trace_->i2c_transfer(topic_, { .v_start = start,
					       .v_end = free_at_,
					       .result = r.error,
					       .messages = traced,
					       .from = port.owner,
					       .note = r.note });
	}
	// (No chip answering is how a bus is scanned: not worth a word.)
	if (!r.note.empty() && r.error != -ENXIO && ++notes_ <= kMaxNotes)
		warn_("/dev/i2c-" + std::to_string(spec_.bus) + ": " + r.note);
	tcs_wire_i2c_reply head{ r.error < 0 ? r.error : int32_t(r.done), uint32_t(data.size()) };
	std::string packet(reinterpret_cast<const char *>(&head), sizeof head);
	port.push(free_at_, packet + data);
}

// I2C_RDWR, read and write: u32 count, the messages' heads, the bytes
// written. The answer: each read message's length (u16) and bytes.
int64_t I2cWire::transfer(WirePort &port, std::string_view payload, int64_t v)
{
	uint32_t count = 0;
	if (payload.size() < sizeof count)
		return -EINVAL;
	memcpy(&count, payload.data(), sizeof count);
	if (count > I2C_RDWR_IOCTL_MAX_MSGS || payload.size() < sizeof count + count * sizeof(tcs_wire_i2c_msg))
		return -EINVAL;
	std::vector<I2cMessage> msgs(count);
	size_t at = sizeof count + count * sizeof(tcs_wire_i2c_msg);
	for (uint32_t i = 0; i < count; i++) {
		tcs_wire_i2c_msg m;
		memcpy(&m, payload.data() + sizeof count + i * sizeof m, sizeof m);
		msgs[i].addr = m.addr;
		msgs[i].flags = m.flags;
		if (m.flags & I2C_M_RD) {
			msgs[i].data.assign(m.len, 0);
			if ((m.flags & I2C_M_RECV_LEN) && m.len > 0) { // (its first byte, which i2c-dev reads)
				if (payload.size() - at < 1)
					return -EINVAL;
				msgs[i].data[0] = uint8_t(payload[at++]);
			}
		} else {
			if (payload.size() - at < m.len)
				return -EINVAL;
			msgs[i].data.assign(payload.begin() + at, payload.begin() + at + m.len);
			at += m.len;
		}
	}
	I2cResult r = i2c_rdwr(bus_, msgs);
	std::string data;
	if (r.error >= 0)
		for (const I2cMessage &m : msgs)
			if (m.flags & I2C_M_RD) {
				const uint16_t len = uint16_t(m.data.size());
				data.append(reinterpret_cast<const char *>(&len), sizeof len);
				data.append(m.data.begin(), m.data.end());
			}
	answer(port, v, r, msgs, data);
	return 0;
}

int64_t I2cWire::smbus(WirePort &port, std::string_view payload, int64_t v)
{
	tcs_wire_smbus s;
	if (payload.size() != sizeof s)
		return -EINVAL;
	memcpy(&s, payload.data(), sizeof s);
	i2c_smbus_data data;
	static_assert(sizeof data == sizeof s.data);
	memcpy(&data, s.data, sizeof data);
	const bool ten = s.addr & 0x8000;
	SmbusResult r = i2c_smbus(bus_, uint16_t(s.addr & 0x3ff), ten, s.read_write, s.command, s.size, &data);
	answer(port, v, r.xfer, r.messages, std::string(reinterpret_cast<const char *>(&data), sizeof data));
	return 0;
}

void I2cWire::trace_topics(std::vector<TraceWireTopic> &out) const
{
	out.push_back({ TraceWireKind::i2c, "dev/i2c-" + std::to_string(spec_.bus) });
}

int64_t I2cWire::take(WirePort &port, uint32_t type, std::string_view payload, int64_t v, const SimWorld *world)
{
	if (type == TCS_WIRE_XFER)
		return transfer(port, payload, v);
	if (type == TCS_WIRE_SMBUS)
		return smbus(port, payload, v);
	return -EINVAL;
}

} // namespace tcs
