// A robot as tcs simulates it, whatever file it came from: the plain data
// that sdf_load.cc reads out of a URDF or SDF file (through libsdformat)
// and ode_robot.cc builds an ODE model of. Nothing here depends on either
// library, so each side is tested on its own, and a description can be
// written by hand (tests, hostile cases).
//
// Frames: every pose is in the model's frame (the frame of the model's
// own <pose>, before the scenario's `pose` moves the whole model), SI
// units, rotations as unit quaternions (w, x, y, z).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace tcs::sim::robot {

using Vec3 = std::array<double, 3>;
using Quat = std::array<double, 4>; // w x y z

struct Pose {
	Vec3 p{ 0, 0, 0 };
	Quat q{ 1, 0, 0, 0 };
};

// Where in the robot file something was declared, for messages: the file
// as given and a 1-based line (0: unknown, the file's name only).
struct Where {
	std::string file;
	int line = 0;
};

struct Shape {
	enum class Kind { box, cylinder, sphere, capsule, plane, mesh };
	Kind kind = Kind::box;
	Vec3 size{ 0, 0, 0 };  // box: x y z (m)
	double radius = 0;     // cylinder, sphere, capsule (m)
	double length = 0;     // cylinder, capsule: along the shape's z (m)
	Vec3 normal{ 0, 0, 1 }; // plane
	// mesh: the triangles as loaded (vertices in the shape's frame,
	// already scaled), three indices a triangle.
	std::vector<Vec3> vertices;
	std::vector<unsigned> indices;
	std::string mesh_uri; // as the file wrote it, for messages
};

struct Collision {
	std::string name;
	Pose pose; // of the shape, in the model's frame
	Shape shape;
	double mu = 1.0; // Coulomb friction (SDF <surface><friction><ode><mu>; URDF: 1)
};

struct Link {
	std::string name;
	Pose pose;         // of the link's frame, in the model's frame
	double mass = 0;   // kg
	Pose inertial;     // of the centre of mass and the inertia's axes, in the model's frame
	// The inertia tensor about the centre of mass, in the inertial frame:
	// ixx iyy izz ixy ixz iyz (kg m^2).
	std::array<double, 6> inertia{ 0, 0, 0, 0, 0, 0 };
	std::vector<Collision> collisions;
	bool self_collide = false; // SDF <self_collide> (model's or link's); off for URDF
	// The model of a world file it came from, when a world's models are
	// simulated as one (robot_file.cc): links of different groups always
	// may touch, of one group only with self_collide (Gazebo's rule).
	int group = 0;
	bool gravity = true;
	Where where;
};

struct Joint {
	enum class Kind { revolute, continuous, prismatic, fixed, ball, universal };
	std::string name;
	Kind kind = Kind::revolute;
	std::string parent; // a link's name, or "world"
	std::string child;  // a link's name
	Pose pose;          // of the joint's frame (its anchor), in the model's frame
	Vec3 axis{ 0, 0, 1 };  // unit, in the model's frame
	Vec3 axis2{ 0, 1, 0 }; // universal only: the second axis, in the model's frame
	// Limits of revolute and prismatic joints (rad or m); none for
	// continuous ones or when the file gives none.
	std::optional<double> lower, upper;
	std::optional<double> effort_limit;   // N*m or N (absent or <= 0 in the file: none)
	std::optional<double> velocity_limit; // rad/s or m/s
	double damping = 0;  // N*m*s/rad or N*s/m
	double friction = 0; // N*m or N (Coulomb, at zero velocity)
	Where where;
};

struct Sensor {
	enum class Kind { imu, force_torque, contact, ray };
	std::string name;
	Kind kind = Kind::imu;
	std::string link;  // the link it is mounted on (force_torque: the joint's child)
	std::string joint; // force_torque only: the joint it measures
	Pose pose;         // in the model's frame
	double rate_hz = 0; // <update_rate>; 0: every step
	// ray: the beam along the sensor's x axis.
	double range_min = 0, range_max = 0;
	Where where;
};

struct Model {
	std::string name; // the file's own name for it (the scenario names the instance)
	Pose pose;        // the model's own <pose> in the world (SDF); identity for URDF
	bool is_static = false;
	std::vector<Link> links;   // at least one; links[0] is the root (URDF's)
	std::vector<Joint> joints; // in file order
	std::vector<Sensor> sensors;
	Where where;
};

// What a file holds: one model (URDF, an SDF <model>), or a world's models
// with its gravity and physics step.
struct Description {
	std::vector<Model> models; // at least one
	std::optional<Vec3> gravity;       // a world's; absent: tcs's default (-9.81 along z)
	std::optional<double> max_step_s;  // a world's <physics><max_step_size>
	std::string file;
};

} // namespace tcs::sim::robot
