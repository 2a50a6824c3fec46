// A one-degree-of-freedom joint (hinge or slider) as its signals see it: a
// continuous position, a velocity, and the effort held on it.
#pragma once

#include <cmath>
#include <string>

#include <ode/ode.h>

namespace tcs::sim {

class Joint1 {
public:
	enum class Kind { hinge, slider };

	// `joint` is already attached, its anchor and axis set with the bodies
	// in their zero pose, and the bodies moved to their initial state, in
	// which a hinge's unwrapped angle is `initial` (a slider reads ODE's).
	Joint1(std::string name, Kind kind, dJointID joint, bool actuated, double damping, double initial);

	const std::string &name() const { return name_; }
	bool actuated() const { return actuated_; }
	const char *position_unit() const { return kind_ == Kind::hinge ? "rad" : "m"; }
	const char *velocity_unit() const { return kind_ == Kind::hinge ? "rad/s" : "m/s"; }
	const char *effort_unit() const { return kind_ == Kind::hinge ? "N*m" : "N"; }

	// Position and velocity at the end of the last step. A hinge's angle is
	// not wrapped: two turns read 4*pi.
	double position() const { return position_; }
	double velocity() const;
	// The commanded effort that was in force during the last step (0
	// before the first step). Damping is the joint's own and not included.
	double effort() const { return applied_; }
	// What the last step added on the joint: the effort less the damping.
	double added() const { return added_; }

	// Holds an effort from the next step on (zero-order hold).
	void command(double effort) { commanded_ = effort; }
	// An actuator's limits (none by default): a command beyond `effort` is
	// applied at it, and none is applied in the direction the joint
	// already moves at `velocity` or faster (the motor cannot drive it
	// faster; gravity and other joints still can).
	void limit(double effort, double velocity)
	{
		effort_limit_ = effort;
		velocity_limit_ = velocity;
	}

	// Before a step: adds the held effort and the damping to ODE's force
	// accumulators (which ODE clears after every step).
	void apply();
	// After a step: follows the angle across ODE's +-pi wrap.
	void update();

private:
	double raw() const;

	std::string name_;
	Kind kind_;
	dJointID joint_;
	bool actuated_;
	double damping_;
	double effort_limit_ = INFINITY;
	double velocity_limit_ = INFINITY;
	double commanded_ = 0;
	double applied_ = 0;
	double added_ = 0;
	double position_;
	double last_raw_;
};

} // namespace tcs::sim
