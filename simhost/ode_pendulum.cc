// The pendulum: a uniform rod hanging from a motorised hinge at one end,
// fixed to the world at the origin. It swings in the x-z plane; angle 0
// hangs straight down (-z), pi is upright, and a positive angle (and a
// positive torque) swings the free end towards +x.
//
// Joint `hinge`: position (rad, continuous), velocity, effort (writable,
// N*m). Link `rod`: pose and twist of its centre of mass.
// Parameters: length (m, 1), mass (kg, 1), damping (N*m*s/rad, 0, a torque
// -damping*velocity), initial_angle (rad, 0), initial_velocity (rad/s, 0).
#include "articulated.h"
#include "body_state.h"

namespace tcs::sim {

namespace {

// Rotating about -y turns the down-pointing rod towards +x.
const dVector3 kAxis = { 0, -1, 0, 0 };

const ParamSpec kParams[] = {
	{ "length", 1.0, Check::positive },
	{ "mass", 1.0, Check::positive },
	{ "damping", 0.0, Check::nonnegative },
	{ "initial_angle", 0.0, Check::finite },
	{ "initial_velocity", 0.0, Check::finite },
};

class Pendulum : public Articulated {
public:
	Pendulum(const std::string &name, const Params &p) : Articulated(name)
	{
		double len = p["length"];
		dBodyID rod = add_link("rod", thin_rod_mass(p["mass"], len));
		const dVector3 pivot = { 0, 0, 0, 0 };
		const dVector3 hanging = { 0, 0, -len / 2, 0 };
		dBodySetPosition(rod, hanging[0], hanging[1], hanging[2]);

		dJointID hinge = dJointCreateHinge(world(), nullptr);
		dJointAttach(hinge, rod, nullptr);
		dJointSetHingeAnchor(hinge, pivot[0], pivot[1], pivot[2]);
		dJointSetHingeAxis(hinge, kAxis[0], kAxis[1], kAxis[2]);

		place_rotated(rod, pivot, kAxis, hanging, p["initial_angle"], p["initial_velocity"]);
		add_joint(Joint1("hinge", Joint1::Kind::hinge, hinge, true, p["damping"], p["initial_angle"]));
	}
};

Result<std::unique_ptr<Model>> make(const std::string &name, const Params &p)
{
	return std::unique_ptr<Model>(new Pendulum(name, p));
}

} // namespace

const ModelType pendulum_model = { "pendulum", kParams, make };

} // namespace tcs::sim
