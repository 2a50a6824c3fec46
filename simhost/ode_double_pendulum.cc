// The double pendulum as an acrobot: two uniform rods in the x-z plane, the
// first on a passive `shoulder` hinge fixed to the world at the origin, the
// second on a motorised `elbow` hinge at the first rod's end. Angles follow
// the pendulum: shoulder 0 hangs straight down, positive swings towards +x;
// the elbow angle is the second rod's angle relative to the first (0 =
// straight on), with the same sense.
//
// Joints: `shoulder` (passive: effort reads 0, not writable) and `elbow`
// (effort writable, N*m). Links `link1`, `link2`.
// Parameters: length1, length2 (m, 1), mass1, mass2 (kg, 1),
// initial_angle1, initial_angle2 (rad, 0), damping (N*m*s/rad, 0, on both
// joints).
#include <cmath>

#include "articulated.h"
#include "body_state.h"

namespace tcs::sim {

namespace {

const dVector3 kAxis = { 0, -1, 0, 0 };

const ParamSpec kParams[] = {
	{ "length1", 1.0, Check::positive },
	{ "length2", 1.0, Check::positive },
	{ "mass1", 1.0, Check::positive },
	{ "mass2", 1.0, Check::positive },
	{ "initial_angle1", 0.0, Check::finite },
	{ "initial_angle2", 0.0, Check::finite },
	{ "damping", 0.0, Check::nonnegative },
};

class DoublePendulum : public Articulated {
public:
	DoublePendulum(const std::string &name, const Params &p) : Articulated(name)
	{
		double l1 = p["length1"], l2 = p["length2"];
		dBodyID link1 = add_link("link1", thin_rod_mass(p["mass1"], l1));
		dBodyID link2 = add_link("link2", thin_rod_mass(p["mass2"], l2));
		dBodySetPosition(link1, 0, 0, -l1 / 2);
		dBodySetPosition(link2, 0, 0, -l1 - l2 / 2);

		dJointID shoulder = dJointCreateHinge(world(), nullptr);
		dJointAttach(shoulder, link1, nullptr);
		dJointSetHingeAnchor(shoulder, 0, 0, 0);
		dJointSetHingeAxis(shoulder, kAxis[0], kAxis[1], kAxis[2]);
		dJointID elbow = dJointCreateHinge(world(), nullptr);
		dJointAttach(elbow, link2, link1);
		dJointSetHingeAnchor(elbow, 0, 0, -l1);
		dJointSetHingeAxis(elbow, kAxis[0], kAxis[1], kAxis[2]);

		// Planar kinematics: a rod at absolute angle a points along
		// (sin a, 0, -cos a).
		double a1 = p["initial_angle1"], a2 = a1 + p["initial_angle2"];
		const dVector3 c1 = { l1 / 2 * std::sin(a1), 0, -l1 / 2 * std::cos(a1), 0 };
		const dVector3 c2 = { l1 * std::sin(a1) + l2 / 2 * std::sin(a2), 0,
				      -l1 * std::cos(a1) - l2 / 2 * std::cos(a2), 0 };
		place_at_rest(link1, c1, kAxis, a1);
		place_at_rest(link2, c2, kAxis, a2);

		double damping = p["damping"];
		add_joint(Joint1("shoulder", Joint1::Kind::hinge, shoulder, false, damping, p["initial_angle1"]));
		add_joint(Joint1("elbow", Joint1::Kind::hinge, elbow, true, damping, p["initial_angle2"]));
	}
};

Result<std::unique_ptr<Model>> make(const std::string &name, const Params &p)
{
	return std::unique_ptr<Model>(new DoublePendulum(name, p));
}

} // namespace

const ModelType double_pendulum_model = { "double_pendulum", kParams, make };

} // namespace tcs::sim
