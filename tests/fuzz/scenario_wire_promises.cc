// The promises of an accepted scenario's wires (see scenario_wire_promises.h),
// written from scenario.h's comments and DESIGN §9, not from the parser.
#include "scenario_wire_promises.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "fuzz_target.h"
#include "scenario_units.h"

namespace scenario_wire_promises {

namespace {

using tcs_fuzz::check;

// A field's bytes by its type; 0 for a type the format does not have.
int type_bytes(const std::string &type)
{
	if (type == "int8" || type == "uint8")
		return 1;
	if (type == "int16" || type == "uint16")
		return 2;
	if (type == "int32" || type == "uint32" || type == "float32")
		return 4;
	return 0;
}

bool model_known(const tcs::Scenario &s, std::string_view model)
{
	return std::any_of(s.models.begin(), s.models.end(), [&](const tcs::ModelSpec &m) { return m.name == model; });
}

// A joint's or link's name: <model>.<part> of a model of the scenario.
void check_part(const tcs::Scenario &s, const tcs::SignalRef &ref)
{
	const std::string signal = ref.name + ".pose"; // what the parts view
	auto parts = tcs::split_signal_name(signal);
	check(parts && ref.line >= 1 && model_known(s, parts->model));
}

// Efforts claimed, as written ("m.j.effort", "m.u.effort[1]"): no two meet.
struct Claims {
	std::vector<std::string> names;
	void add(const std::string &name)
	{
		auto x = tcs::split_signal_index(name);
		check(x.has_value());
		for (const std::string &o : names) {
			auto y = tcs::split_signal_index(o);
			check(x->signal != y->signal || (x->index >= 0 && y->index >= 0 && x->index != y->index));
		}
		names.push_back(name);
	}
};

void add_joint(std::vector<std::string> *known, const std::string &joint)
{
	for (const char *f : { ".position", ".velocity", ".effort" })
		known->push_back(joint + f);
}

void check_frame(const tcs::Scenario &s, const tcs::CanSpec &c, const tcs::CanFrameSpec &f, Claims *claims,
		 std::vector<std::string> *known)
{
	check(f.line >= 1 && f.id <= (f.extended ? 0x1FFFFFFFu : 0x7FFu));
	if (f.command)
		check(f.rate_hz == 0 && f.period_ns == 0 && !f.fields.empty());
	else
		check(f.rate_hz >= 1e-6 && f.rate_hz <= 1e9 && f.period_ns == tcs::rate_period_ns(f.rate_hz));
	const int payload = c.data_bitrate ? 64 : 8;
	std::vector<bool> used(payload, false);
	for (const tcs::CanFieldSpec &field : f.fields) {
		const int size = type_bytes(field.type);
		check(size > 0 && field.start >= 0 && field.start + size <= payload && field.line >= 1);
		for (int b = field.start; b < field.start + size; b++) {
			check(!used[b]);
			used[b] = true;
		}
		check(std::isfinite(field.scale) && field.scale != 0 && std::isfinite(field.offset));
		auto ix = tcs::split_signal_index(field.signal.name);
		check(ix && field.signal.line >= 1);
		auto parts = tcs::split_signal_name(ix->signal);
		check(parts && model_known(s, parts->model));
		const int width = tcs::signal_field_width(parts->field);
		check(ix->index < width && (ix->index >= 0 || width <= 2));
		if (f.command) {
			check(parts->field == "effort");
			claims->add(field.signal.name);
		}
		known->push_back(std::string(ix->signal));
	}
}

void check_cans(const tcs::Scenario &s, Claims *claims, std::vector<std::string> *known)
{
	for (size_t i = 0; i < s.cans.size(); i++) {
		const tcs::CanSpec &c = s.cans[i];
		check(tcs::is_interface_name(c.interface) && c.line >= 1);
		for (size_t j = 0; j < i; j++)
			check(s.cans[j].interface != c.interface);
		check(c.bitrate >= 10000 && c.bitrate <= 1000000);
		check(c.data_bitrate == 0 || (c.data_bitrate >= c.bitrate && c.data_bitrate <= 8000000));
		std::set<std::pair<uint32_t, bool>> ids; // (id, extended)
		for (const tcs::CanMotorSpec &m : c.motors) {
			check(m.protocol == "mit" && m.line >= 1 && m.id >= 1 && m.id <= 0x7FF && m.reply_id <= 0x7FF);
			check(ids.insert({ m.id, false }).second);
			for (double range : { m.position_range, m.velocity_range, m.torque_range, m.kp_max, m.kd_max })
				check(std::isfinite(range) && range > 0);
			check_part(s, m.joint);
			claims->add(m.joint.name + ".effort");
			add_joint(known, m.joint.name);
		}
		for (const tcs::CanFrameSpec &f : c.frames) {
			check(ids.insert({ f.id, f.extended }).second);
			check_frame(s, c, f, claims, known);
		}
	}
}

bool is_baud(int64_t b)
{
	return b == 50 || b == 75 || b == 110 || b == 134 || b == 150 || b == 200 || (b >= 300 && b <= 4000000);
}

} // namespace

void check_wires(const tcs::Scenario &s, std::vector<std::string> *known)
{
	Claims claims;
	std::vector<std::string> paths;
	for (const tcs::DeviceSpec &d : s.devices) {
		paths.push_back(d.path);
		if (d.kind == tcs::DeviceSpec::Kind::Actuator)
			for (const tcs::SignalRef &sig : d.signals)
				claims.add(sig.name);
	}
	check_cans(s, &claims, known);
	for (const tcs::SerialSpec &l : s.serials) {
		check(tcs::is_normal_absolute_path(l.path) && l.line >= 1 && is_baud(l.baud));
		check(std::find(paths.begin(), paths.end(), l.path) == paths.end());
		paths.push_back(l.path);
		std::set<uint32_t> ids;
		for (const tcs::ServoSpec &v : l.servos) {
			check(v.protocol == "dynamixel2" && v.id <= 252 && v.line >= 1 && ids.insert(v.id).second);
			check_part(s, v.joint);
			claims.add(v.joint.name + ".effort");
			add_joint(known, v.joint.name);
		}
	}
	std::set<int> buses;
	for (const tcs::I2cSpec &b : s.i2cs) {
		check(b.bus >= 0 && b.bus <= 255 && buses.insert(b.bus).second && b.line >= 1);
		const std::string path = "/dev/i2c-" + std::to_string(b.bus);
		check(std::find(paths.begin(), paths.end(), path) == paths.end());
		check(b.clock_hz >= 10000 && b.clock_hz <= 3400000);
		std::set<uint32_t> addresses;
		for (const tcs::I2cDeviceSpec &d : b.devices) {
			check(d.address >= 0x03 && d.address <= 0x77 && addresses.insert(d.address).second);
			check(d.chip == "mpu6050" && (d.address == 0x68 || d.address == 0x69) && d.line >= 1);
			check(std::isfinite(d.accel_noise) && d.accel_noise >= 0);
			check(std::isfinite(d.gyro_noise) && d.gyro_noise >= 0);
			check_part(s, d.link);
			known->push_back(d.link.name + ".pose");
			known->push_back(d.link.name + ".twist");
		}
	}
}

} // namespace scenario_wire_promises
