// The common shape of the pendulum, cart-pole and acrobot: rigid links
// joined by one-degree-of-freedom joints in their own ODE world, without
// contacts, stepped with ODE's exact (Dantzig LCP) stepper for accuracy.
// Signals, in this order: per joint <name>.<joint>.position, .velocity,
// .effort (writable when the joint is motorised), then per link
// <name>.<link>.pose and .twist.
#pragma once

#include <string>
#include <vector>

#include <ode/ode.h>

#include "joint1.h"
#include "model.h"

namespace tcs::sim {

class Articulated : public Model {
public:
	~Articulated() override;
	Articulated(const Articulated &) = delete;
	Articulated &operator=(const Articulated &) = delete;

	void describe(std::vector<SignalDesc> &out) const override;
	void read(uint32_t local, double *out) const override;
	void write(uint32_t local, const double *values) override;
	Status step(double dt) override;

protected:
	explicit Articulated(std::string name);

	dWorldID world() const { return world_; }
	// A body at the origin with identity orientation (the zero pose).
	dBodyID add_link(const char *link, const dMass &mass);
	void add_joint(Joint1 joint) { joints_.push_back(std::move(joint)); }

private:
	struct Link {
		std::string name;
		dBodyID body;
	};

	std::string name_;
	dWorldID world_;
	std::vector<Joint1> joints_;
	std::vector<Link> links_;
};

// The mass of a uniform thin rod along the body's z axis, centred. Its
// axial inertia is that of a radius of 1 % of the length: ODE needs it
// positive, and no motion of these models depends on it.
dMass thin_rod_mass(double mass, double length);

} // namespace tcs::sim
