// Who drives an effort (see scenario_drivers.h).
#include "scenario_drivers.h"

#include "scenario_reader.h"
#include "scenario_units.h"

namespace tcs::scenario_parse {

namespace {

// Whether two claims, each a signal with or without an index, meet.
bool meet(std::string_view a, std::string_view b)
{
	auto x = split_signal_index(a), y = split_signal_index(b);
	if (!x || !y || x->signal != y->signal)
		return false;
	return x->index < 0 || y->index < 0 || x->index == y->index;
}

std::string at(const std::string &what, int line)
{
	return what + " (line " + std::to_string(line) + ")";
}

} // namespace

std::optional<std::string> effort_driver(const Scenario &sc, std::string_view effort)
{
	for (const DeviceSpec &d : sc.devices)
		if (d.kind == DeviceSpec::Kind::Actuator)
			for (const SignalRef &s : d.signals)
				if (meet(s.name, effort))
					return at(d.path, s.line);
	for (const CanSpec &c : sc.cans) {
		for (const CanMotorSpec &m : c.motors)
			if (meet(m.joint.name + ".effort", effort))
				return at("motor " + hex(m.id, 3) + " on " + c.interface, m.joint.line);
		for (const CanFrameSpec &f : c.frames)
			if (f.command)
				for (const CanFieldSpec &field : f.fields)
					if (meet(field.signal.name, effort))
						return at("command frame " + hex(f.id, f.extended ? 8 : 3) + " on " +
								  c.interface,
							  field.signal.line);
	}
	for (const SerialSpec &s : sc.serials)
		for (const ServoSpec &v : s.servos)
			if (meet(v.joint.name + ".effort", effort))
				return at("servo " + std::to_string(v.id) + " on " + s.path, v.joint.line);
	return std::nullopt;
}

} // namespace tcs::scenario_parse
