// Signals and stepping shared by the articulated models.
#include "articulated.h"

#include <cassert>

#include "body_state.h"

namespace tcs::sim {

Articulated::Articulated(std::string name) : name_(std::move(name)), world_(dWorldCreate())
{
	dWorldSetGravity(world_, 0, 0, -kGravity);
	// Stiff joints: the default double-precision CFM, said explicitly
	// because the accuracy tests depend on it.
	dWorldSetCFM(world_, 1e-10);
}

Articulated::~Articulated()
{
	dWorldDestroy(world_); // and with it the bodies and joints
}

dBodyID Articulated::add_link(const char *link, const dMass &mass)
{
	dBodyID b = dBodyCreate(world_);
	dBodySetMass(b, &mass);
	links_.push_back(Link{ link, b });
	return b;
}

void Articulated::describe(std::vector<SignalDesc> &out) const
{
	for (const Joint1 &j : joints_) {
		std::string p = name_ + "." + j.name() + ".";
		out.push_back({ p + "position", 1, 0, j.position_unit() });
		out.push_back({ p + "velocity", 1, 0, j.velocity_unit() });
		out.push_back({ p + "effort", 1, j.actuated() ? (uint32_t)TCS_SIM_SIGNAL_WRITABLE : 0u, j.effort_unit() });
	}
	for (const Link &l : links_) {
		std::string p = name_ + "." + l.name + ".";
		out.push_back({ p + "pose", 7, 0, "m, quaternion" });
		out.push_back({ p + "twist", 6, 0, "m/s, rad/s" });
	}
}

void Articulated::read(uint32_t local, double *out) const
{
	size_t nj = 3 * joints_.size();
	if (local < nj) {
		const Joint1 &j = joints_[local / 3];
		switch (local % 3) {
		case 0:
			out[0] = j.position();
			break;
		case 1:
			out[0] = j.velocity();
			break;
		default:
			out[0] = j.effort();
			break;
		}
		return;
	}
	const Link &l = links_[(local - nj) / 2];
	if ((local - nj) % 2 == 0)
		read_pose(l.body, out);
	else
		read_twist(l.body, out);
}

void Articulated::write(uint32_t local, const double *values)
{
	// The world only passes signals describe() marked writable: efforts.
	assert(local < 3 * joints_.size() && local % 3 == 2);
	joints_[local / 3].command(values[0]);
}

Status Articulated::step(double dt)
{
	for (Joint1 &j : joints_)
		j.apply();
	if (!dWorldStep(world_, dt))
		return Error{ "ODE could not allocate the memory for a step" };
	for (Joint1 &j : joints_)
		j.update();
	for (const Link &l : links_)
		if (!body_finite(l.body))
			return Error{ "the state became non-finite (an effort too large for the step?)" };
	return Ok{};
}

dMass thin_rod_mass(double mass, double length)
{
	double perp = mass * length * length / 12;
	double r = 0.01 * length;
	dMass m;
	dMassSetParameters(&m, mass, 0, 0, 0, perp, perp, mass * r * r / 2, 0, 0, 0);
	return m;
}

} // namespace tcs::sim
