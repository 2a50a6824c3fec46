// The robot model: built from a checked description in the order ODE needs
// (bodies and geoms in the zero pose, joints, then the initial state),
// its signal table, and the step.
//
// Stepper: ODE's exact one (dWorldStep, a Dantzig LCP per group of
// connected bodies) while the joints and this step's contacts make at most
// kExactRows constraint rows: it is accurate (energy, stops, friction held
// exactly) and cheap for robots of tens of links. Its cost grows with the
// cube of the rows (and its memory with their square), so a larger model
// or a pile of contacts takes the iterative dWorldQuickStep instead (run
// under the world's own random state, so it stays repeatable).
#include "ode_robot.h"

#include <cstdint>

#include <ode/ode.h>

#include "body_state.h"
#include "frames.h"
#include "ode_init.h"
#include "quick_step.h"
#include "robot_check.h"
#include "robot_collide.h"
#include "robot_joints.h"
#include "robot_links.h"
#include "robot_sensors.h"

namespace tcs::sim {

namespace {

using robot::Collider;
using robot::Pose;
using robot::RobotJoints;
using robot::RobotLink;
using robot::Sensor;
using robot::Sensors;
using robot::Topology;
using robot::Universal;
using robot::Vec3;

// Rows past which the exact stepper gives way. Measured (ODE 0.16, one
// core) on chains of hinges: 30 links (150 rows) 0.3 ms a step exact, 0.2
// ms iterative; 60 links (300 rows) 3 ms exact, 0.6 ms iterative. 200 rows
// keep an exact step near 1 ms.
constexpr size_t kExactRows = 200;
// QuickStep's iterations: Gazebo's default; ODE's 20 lets chains sag more.
constexpr int kQuickIterations = 50;

// Where a signal's value comes from.
struct Channel {
	enum class Source : uint8_t { joint1, universal, link, sensor } source;
	uint32_t index;
	uint32_t field; // joint: position, velocity, effort; link: pose, twist; sensor: its fields
};

class RobotModel final : public Model {
public:
	RobotModel(std::string name, const Vec3 &gravity) : name_(std::move(name)), world_(dWorldCreate())
	{
		dWorldSetGravity(world_, gravity[0], gravity[1], gravity[2]);
		// Stiff joints, as the built-in models have (Articulated).
		dWorldSetCFM(world_, 1e-10);
		dWorldSetQuickStepNumIterations(world_, kQuickIterations);
		sensors_ = std::make_unique<Sensors>(gravity);
	}

	~RobotModel() override
	{
		sensors_.reset(); // ray geoms
		collider_.reset(); // space, geoms, contact joints
		dWorldDestroy(world_);
	}

	void build(const robot::Model &desc, const Topology &topo, const Pose &model_in_world,
		   const RobotOptions &opts);

	void describe(std::vector<SignalDesc> &out) const override
	{
		out.insert(out.end(), descs_.begin(), descs_.end());
	}
	void read(uint32_t local, double *out) const override;
	void write(uint32_t local, const double *values) override;
	Status step(double dt) override;

private:
	void add_signal(const std::string &what, uint32_t width, bool writable, const char *unit, Channel c,
			double rate_hz = 0)
	{
		descs_.push_back({ name_ + "." + what, width, writable ? (uint32_t)TCS_SIM_SIGNAL_WRITABLE : 0u, unit,
				   rate_hz });
		channels_.push_back(c);
	}
	void describe_signals(const robot::Model &desc);

	std::string name_;
	dWorldID world_;
	std::vector<RobotLink> links_;
	std::unique_ptr<Collider> collider_;
	RobotJoints joints_;
	std::unique_ptr<Sensors> sensors_;
	QuickStepper quick_;
	std::vector<SignalDesc> descs_;
	std::vector<Channel> channels_;
};

void RobotModel::build(const robot::Model &desc, const Topology &topo, const Pose &model_in_world,
		       const RobotOptions &opts)
{
	collider_ = std::make_unique<Collider>(world_, desc.links.size());
	links_.reserve(desc.links.size());
	for (size_t i = 0; i < desc.links.size(); i++) {
		links_.push_back(robot::make_link(world_, desc.links[i], model_in_world, topo.anchored[i]));
		collider_->add_link(i, desc.links[i], links_.back(), model_in_world);
	}
	for (size_t j = 0; j < desc.joints.size(); j++)
		if (topo.joint_parent[j] >= 0)
			collider_->join((size_t)topo.joint_parent[j], topo.joint_child[j]);
	joints_ = robot::make_joints(world_, desc, topo, links_, model_in_world, opts);
	for (const Sensor &s : desc.sensors)
		sensors_->add(s, desc, topo, links_, joints_, *collider_, model_in_world);
	collider_->finish();
	sensors_->update(0, links_, *collider_);
	describe_signals(desc);
}

void RobotModel::describe_signals(const robot::Model &desc)
{
	for (const RobotJoints::Moving &m : joints_.moving) {
		if (m.universal) {
			const std::string p = joints_.two[m.index].name() + ".";
			Channel c{ Channel::Source::universal, (uint32_t)m.index, 0 };
			add_signal(p + "position", 2, false, "rad", c);
			add_signal(p + "velocity", 2, false, "rad/s", { c.source, c.index, 1 });
			add_signal(p + "effort", 2, true, "N*m", { c.source, c.index, 2 });
			continue;
		}
		const Joint1 &j = joints_.one[m.index];
		const std::string p = j.name() + ".";
		Channel c{ Channel::Source::joint1, (uint32_t)m.index, 0 };
		add_signal(p + "position", 1, false, j.position_unit(), c);
		add_signal(p + "velocity", 1, false, j.velocity_unit(), { c.source, c.index, 1 });
		add_signal(p + "effort", 1, true, j.effort_unit(), { c.source, c.index, 2 });
	}
	for (size_t i = 0; i < links_.size(); i++) {
		add_signal(links_[i].name + ".pose", 7, false, "m, quaternion",
			   { Channel::Source::link, (uint32_t)i, 0 });
		add_signal(links_[i].name + ".twist", 6, false, "m/s, rad/s",
			   { Channel::Source::link, (uint32_t)i, 1 });
	}
	for (size_t i = 0; i < desc.sensors.size(); i++) {
		auto fields = robot::sensor_fields(desc.sensors[i].kind);
		for (size_t f = 0; f < fields.size(); f++)
			add_signal(desc.sensors[i].name + "." + fields[f].name, fields[f].width, false, fields[f].unit,
				   { Channel::Source::sensor, (uint32_t)i, (uint32_t)f }, desc.sensors[i].rate_hz);
	}
}

void RobotModel::read(uint32_t local, double *out) const
{
	const Channel &c = channels_[local];
	switch (c.source) {
	case Channel::Source::joint1: {
		const Joint1 &j = joints_.one[c.index];
		out[0] = c.field == 0 ? j.position() : c.field == 1 ? j.velocity() : j.effort();
		break;
	}
	case Channel::Source::universal: {
		const Universal &u = joints_.two[c.index];
		for (int i = 0; i < 2; i++)
			out[i] = c.field == 0 ? u.position(i) : c.field == 1 ? u.velocity(i) : u.effort(i);
		break;
	}
	case Channel::Source::link:
		if (c.field == 0)
			robot::read_link_pose(links_[c.index], out);
		else
			robot::read_link_twist(links_[c.index], out);
		break;
	case Channel::Source::sensor:
		sensors_->read(c.index, c.field, out);
		break;
	}
}

void RobotModel::write(uint32_t local, const double *values)
{
	// The world passes only what describe() marked writable: efforts.
	const Channel &c = channels_[local];
	if (c.source == Channel::Source::joint1)
		joints_.one[c.index].command(values[0]);
	else if (c.source == Channel::Source::universal)
		joints_.two[c.index].command(values);
}

Status RobotModel::step(double dt)
{
	joints_.apply();
	size_t contacts = collider_->collide();
	int ok = joints_.rows + 3 * contacts <= kExactRows ? dWorldStep(world_, dt) : quick_.step(world_, dt);
	collider_->after_step();
	if (!ok)
		return Error{ "ODE could not allocate the memory for a step" };
	joints_.update();
	for (const RobotLink &l : links_)
		if (l.body && !body_finite(l.body))
			return Error{ "link '" + l.name +
				      "': the state became non-finite (an effort too large for the step?)" };
	sensors_->update(dt, links_, *collider_);
	return Ok{};
}

} // namespace

Result<std::unique_ptr<Model>> make_robot_model(const std::string &name, const robot::Model &desc,
						const RobotOptions &opts)
{
	if (auto s = ode_ready(); !s)
		return s.error();
	auto topo = robot::check_robot(desc, opts);
	if (!topo)
		return topo.error();
	// The model's frame in the world: the scenario places the root link,
	// or the description places the model.
	Pose model_in_world{ desc.pose.p, robot::normalized(desc.pose.q) };
	if (opts.pose) {
		Pose root{ desc.links[0].pose.p, robot::normalized(desc.links[0].pose.q) };
		model_in_world =
			robot::compose({ opts.pose->p, robot::normalized(opts.pose->q) }, robot::inverse(root));
	}
	auto model = std::make_unique<RobotModel>(name, opts.gravity);
	model->build(desc, *topo, model_in_world, opts);
	return std::unique_ptr<Model>(std::move(model));
}

} // namespace tcs::sim
