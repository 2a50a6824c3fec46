// The cart-pole: a cart on a motorised slider along x, fixed to the world,
// carrying a uniform pole on a passive hinge at the cart's centre. As in
// the cart-pole literature (and unlike the pendulum), the pole's angle 0 is
// UPRIGHT (+z); a positive angle tilts its top towards +x; pi hangs down.
//
// Joints: `slider` (position m, velocity m/s, effort N: writable, the force
// on the cart) and `hinge` (position rad, continuous; velocity; effort,
// passive: reads 0, not writable). Links `cart` and `pole`.
// Parameters: cart_mass (kg, 1), pole_mass (kg, 0.1), pole_length (m, 1),
// initial_angle (rad, 0: balanced, so give it a nudge), track_limit (m,
// optional: the cart stops at +-track_limit; without it the track is
// endless).
#include "articulated.h"
#include "body_state.h"

namespace tcs::sim {

namespace {

// Rotating about +y tilts the upright pole's top towards +x.
const dVector3 kAxis = { 0, 1, 0, 0 };

const ParamSpec kParams[] = {
	{ "cart_mass", 1.0, Check::positive },
	{ "pole_mass", 0.1, Check::positive },
	{ "pole_length", 1.0, Check::positive },
	{ "initial_angle", 0.0, Check::finite },
	{ "track_limit", NAN, Check::positive },
};

class Cartpole : public Articulated {
public:
	Cartpole(const std::string &name, const Params &p) : Articulated(name)
	{
		// The cart's shape only sets its inertia, which the slider makes
		// irrelevant: it cannot rotate.
		dMass cm;
		dMassSetBoxTotal(&cm, p["cart_mass"], 0.4, 0.2, 0.2);
		dBodyID cart = add_link("cart", cm);

		double len = p["pole_length"];
		dBodyID pole = add_link("pole", thin_rod_mass(p["pole_mass"], len));
		const dVector3 pivot = { 0, 0, 0, 0 };
		const dVector3 upright = { 0, 0, len / 2, 0 };
		dBodySetPosition(pole, upright[0], upright[1], upright[2]);

		dJointID slider = dJointCreateSlider(world(), nullptr);
		dJointAttach(slider, cart, nullptr);
		dJointSetSliderAxis(slider, 1, 0, 0);
		if (p.has("track_limit")) {
			dJointSetSliderParam(slider, dParamLoStop, -p["track_limit"]);
			dJointSetSliderParam(slider, dParamHiStop, p["track_limit"]);
		}

		dJointID hinge = dJointCreateHinge(world(), nullptr);
		dJointAttach(hinge, pole, cart);
		dJointSetHingeAnchor(hinge, pivot[0], pivot[1], pivot[2]);
		dJointSetHingeAxis(hinge, kAxis[0], kAxis[1], kAxis[2]);

		place_rotated(pole, pivot, kAxis, upright, p["initial_angle"], 0);
		add_joint(Joint1("slider", Joint1::Kind::slider, slider, true, 0, 0));
		add_joint(Joint1("hinge", Joint1::Kind::hinge, hinge, false, 0, p["initial_angle"]));
	}
};

Result<std::unique_ptr<Model>> make(const std::string &name, const Params &p)
{
	return std::unique_ptr<Model>(new Cartpole(name, p));
}

} // namespace

const ModelType cartpole_model = { "cartpole", kParams, make };

} // namespace tcs::sim
