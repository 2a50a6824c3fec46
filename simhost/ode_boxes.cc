// Boxes: `count` cubes sliding and colliding on a floor enclosed by four
// walls, started with random velocities from a fixed seed. It is the
// variable-cost workload of the TCS paper's Figure 1: a step's cost follows
// how many boxes are near each other, which changes as they scatter.
//
// Signals: <name>.box<i>.pose and .twist for each box, then
// <name>.arena.contacts, the number of contact points of the last step.
// Parameters: count (1000), box_size (m, 0.1: the cube's edge), seed (1),
// friction (Coulomb coefficient, 0.05), speed (m/s, 2: initial speeds are
// uniform in [0, speed]), arena_size (m: the inside edge of the square
// enclosure; by default the boxes cover a tenth of the floor).
//
// The same parameters give the same motion, run after run and in several
// worlds stepped in any interleaving: the initial state comes from a
// specified generator (mt19937_64, own uniform mapping), and ODE's global
// random generator, which its iterative solver uses to reorder
// constraints, is saved and restored per world around every step.
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <ode/ode.h>

#include "body_state.h"
#include "model.h"
#include "quick_step.h"

namespace tcs::sim {

namespace {

const ParamSpec kParams[] = {
	{ "count", 1000, Check::count },
	{ "box_size", 0.1, Check::positive },
	{ "seed", 1, Check::natural },
	{ "friction", 0.05, Check::nonnegative },
	{ "speed", 2.0, Check::nonnegative },
	{ "arena_size", NAN, Check::positive },
};

constexpr size_t kMaxCount = 100000;
constexpr int kMaxContacts = 8; // box-box gives up to 8, box-plane 4
constexpr double kDensity = 500; // kg/m^3, a wooden crate's
constexpr double kBounce = 0.3;

class Boxes : public Model {
public:
	Boxes(std::string name, size_t count, double size, double arena, double friction)
		: name_(std::move(name)), size_(size), friction_(friction), world_(dWorldCreate()),
		  space_(dHashSpaceCreate(nullptr)), contacts_(dJointGroupCreate(0))
	{
		dWorldSetGravity(world_, 0, 0, -kGravity);
		// Slightly soft contacts and a millimetre of allowed overlap keep
		// resting boxes from jittering and the iterative solver stable.
		dWorldSetCFM(world_, 1e-5);
		dWorldSetContactSurfaceLayer(world_, 0.001);
		// Hash cells from half to eight times the box: a box's bounding
		// box then spans few cells.
		int level = (int)std::floor(std::log2(size));
		dHashSpaceSetLevels(space_, level - 1, level + 3);

		// Floor, and the walls (planes keep the side a*x+b*y+c*z < d solid).
		dCreatePlane(space_, 0, 0, 1, 0);
		dCreatePlane(space_, 1, 0, 0, -arena / 2);
		dCreatePlane(space_, -1, 0, 0, -arena / 2);
		dCreatePlane(space_, 0, 1, 0, -arena / 2);
		dCreatePlane(space_, 0, -1, 0, -arena / 2);

		dMass m;
		dMassSetBox(&m, kDensity, size, size, size);
		bodies_.reserve(count);
		for (size_t i = 0; i < count; i++) {
			dBodyID b = dBodyCreate(world_);
			dBodySetMass(b, &m);
			dGeomSetBody(dCreateBox(space_, size, size, size), b);
			bodies_.push_back(b);
		}
	}

	~Boxes() override
	{
		dJointGroupDestroy(contacts_);
		dSpaceDestroy(space_); // and its geoms
		dWorldDestroy(world_);
	}

	Boxes(const Boxes &) = delete;
	Boxes &operator=(const Boxes &) = delete;

	// Puts the boxes on a grid of cells (so none overlap), each jittered
	// and turned at random in its cell, moving in a random direction.
	void scatter(uint64_t seed, double arena, double speed)
	{
		std::mt19937_64 rng(seed);
		// Not std::uniform_real_distribution: its output is the library's
		// choice, and the same seed must give the same boxes everywhere.
		auto uniform = [&rng] { return (double)(rng() >> 11) * 0x1p-53; };

		size_t cells = (size_t)std::ceil(std::sqrt((double)bodies_.size()));
		double pitch = arena / (double)cells;
		double slack = (pitch - size_ * M_SQRT2) / 2; // a turned box stays in its cell
		const dVector3 up = { 0, 0, 1, 0 };
		for (size_t i = 0; i < bodies_.size(); i++) {
			dVector3 pos = { -arena / 2 + ((double)(i % cells) + 0.5) * pitch + slack * (2 * uniform() - 1),
					 -arena / 2 + ((double)(i / cells) + 0.5) * pitch + slack * (2 * uniform() - 1),
					 size_ / 2, 0 };
			place_at_rest(bodies_[i], pos, up, 2 * M_PI * uniform());
			double dir = 2 * M_PI * uniform(), v = speed * uniform();
			dBodySetLinearVel(bodies_[i], v * std::cos(dir), v * std::sin(dir), 0);
		}
	}

	void describe(std::vector<SignalDesc> &out) const override
	{
		for (size_t i = 0; i < bodies_.size(); i++) {
			std::string p = name_ + ".box" + std::to_string(i) + ".";
			out.push_back({ p + "pose", 7, 0, "m, quaternion" });
			out.push_back({ p + "twist", 6, 0, "m/s, rad/s" });
		}
		out.push_back({ name_ + ".arena.contacts", 1, 0, "1" });
	}

	void read(uint32_t local, double *out) const override
	{
		if (local == 2 * bodies_.size()) {
			out[0] = (double)ncontacts_;
			return;
		}
		if (local % 2 == 0)
			read_pose(bodies_[local / 2], out);
		else
			read_twist(bodies_[local / 2], out);
	}

	void write(uint32_t, const double *) override {} // nothing is writable

	Status step(double dt) override
	{
		ncontacts_ = 0;
		dSpaceCollide(space_, this, &Boxes::near);
		int ok = stepper_.step(world_, dt);
		dJointGroupEmpty(contacts_);
		if (!ok)
			return Error{ "ODE could not allocate the memory for a step" };
		for (dBodyID b : bodies_)
			if (!body_finite(b))
				return Error{ "the state became non-finite" };
		return Ok{};
	}

private:
	// dSpaceCollide's callback: contact joints for one pair of geoms that
	// are near each other (their bounding boxes overlap).
	static void near(void *data, dGeomID a, dGeomID b)
	{
		Boxes *self = static_cast<Boxes *>(data);
		dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
		if (!ba && !bb)
			return; // floor and walls meet only each other
		dContact c[kMaxContacts];
		int n = dCollide(a, b, kMaxContacts, &c[0].geom, sizeof c[0]);
		for (int i = 0; i < n; i++) {
			c[i].surface.mode = dContactBounce | dContactApprox1;
			c[i].surface.mu = self->friction_;
			c[i].surface.bounce = kBounce;
			c[i].surface.bounce_vel = 0.05;
			dJointID j = dJointCreateContact(self->world_, self->contacts_, &c[i]);
			dJointAttach(j, ba, bb);
		}
		self->ncontacts_ += (uint32_t)n;
	}

	std::string name_;
	double size_;
	double friction_;
	dWorldID world_;
	dSpaceID space_;
	dJointGroupID contacts_;
	std::vector<dBodyID> bodies_;
	uint32_t ncontacts_ = 0;
	QuickStepper stepper_;
};

Result<std::unique_ptr<Model>> make(const std::string &name, const Params &p)
{
	// A bound that keeps a typo from asking for terabytes.
	if (p["count"] > kMaxCount)
		return Error{ "parameter 'count' must be at most " + std::to_string(kMaxCount) };
	size_t count = (size_t)p["count"];
	double size = p["box_size"];
	// A tenth of the floor covered: room to slide, and crowds to collide.
	double arena = p.has("arena_size") ? p["arena_size"] : size * std::sqrt((double)count / 0.1);
	double cells = std::ceil(std::sqrt((double)count));
	double needed = cells * size * M_SQRT2;
	if (arena < needed) {
		char buf[160];
		snprintf(buf, sizeof buf, "%zu boxes of %g m do not fit in an arena of %g m (it needs %.3g m)",
			 count, size, arena, needed);
		return Error{ buf };
	}
	auto boxes = std::make_unique<Boxes>(name, count, size, arena, p["friction"]);
	boxes->scatter((uint64_t)p["seed"], arena, p["speed"]);
	return std::unique_ptr<Model>(std::move(boxes));
}

} // namespace

const ModelType boxes_model = { "boxes", kParams, make };

} // namespace tcs::sim
