// One-degree-of-freedom joints: efforts applied by zero-order hold, and a
// hinge angle kept continuous across ODE's wrap at +-pi.
#include "joint1.h"

#include <algorithm>
#include <cmath>

namespace tcs::sim {

Joint1::Joint1(std::string name, Kind kind, dJointID joint, bool actuated, double damping, double initial)
	: name_(std::move(name)), kind_(kind), joint_(joint), actuated_(actuated), damping_(damping)
{
	last_raw_ = raw();
	// ODE only knows the angle modulo 2*pi; the model knows how many turns.
	position_ = kind_ == Kind::hinge ? initial : last_raw_;
}

double Joint1::raw() const
{
	return kind_ == Kind::hinge ? dJointGetHingeAngle(joint_) : dJointGetSliderPosition(joint_);
}

double Joint1::velocity() const
{
	return kind_ == Kind::hinge ? dJointGetHingeAngleRate(joint_) : dJointGetSliderPositionRate(joint_);
}

void Joint1::apply()
{
	double v = velocity();
	applied_ = std::clamp(commanded_, -effort_limit_, effort_limit_);
	if ((applied_ > 0 && v >= velocity_limit_) || (applied_ < 0 && v <= -velocity_limit_))
		applied_ = 0;
	// Explicit damping from the last step's velocity: at the step sizes
	// used (ms) and the damping of a real joint it is stable and simple.
	double f = applied_ - damping_ * v;
	added_ = f;
	if (f == 0)
		return;
	if (kind_ == Kind::hinge)
		dJointAddHingeTorque(joint_, f);
	else
		dJointAddSliderForce(joint_, f);
}

void Joint1::update()
{
	double r = raw();
	if (kind_ == Kind::hinge)
		position_ += std::remainder(r - last_raw_, 2 * M_PI);
	else
		position_ = r;
	last_raw_ = r;
}

} // namespace tcs::sim
