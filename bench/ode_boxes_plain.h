// The world of simhost's `boxes` model at its default parameters, written
// as a hand-made ODE program would be: a world, a hash space, a near
// callback filling a contact joint group, dWorldQuickStep. Only ODE, no tcs
// code: it is the baseline the plug-in is measured against, so every
// setting and every number drawn must equal those of simhost/ode_boxes.cc,
// or the two would not do the same work (checked by the checksum).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include <ode/ode.h>

namespace plain {

constexpr size_t kCount = 1000;
constexpr double kSize = 0.1; // m, a cube's edge
constexpr uint64_t kSeed = 1;
constexpr double kFriction = 0.05;
constexpr double kSpeed = 2.0; // m/s: initial speeds are uniform in [0, kSpeed]
constexpr double kDensity = 500; // kg/m^3
constexpr double kGravity = 9.81;
constexpr double kStep = 0.001; // s
constexpr int kMaxContacts = 8; // box-box gives up to 8

struct Boxes {
	dWorldID world = nullptr;
	dSpaceID space = nullptr;
	dJointGroupID contacts = nullptr;
	std::vector<dBodyID> bodies;
};

inline void near_callback(void *data, dGeomID a, dGeomID b)
{
	Boxes *w = static_cast<Boxes *>(data);
	dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
	if (!ba && !bb)
		return; // two of the fixed planes
	dContact c[kMaxContacts];
	int n = dCollide(a, b, kMaxContacts, &c[0].geom, sizeof c[0]);
	for (int i = 0; i < n; i++) {
		c[i].surface.mode = dContactBounce | dContactApprox1;
		c[i].surface.mu = kFriction;
		c[i].surface.bounce = 0.3;
		c[i].surface.bounce_vel = 0.05;
		dJointAttach(dJointCreateContact(w->world, w->contacts, &c[i]), ba, bb);
	}
}

// Boxes on a grid of cells, each jittered and turned at random in its
// cell, sliding in a random direction. The draws are the model's: its
// generator is the standard's mt19937_64, mapped to [0, 1) by the top 53
// bits, drawn in the same order.
inline void boxes_scatter(Boxes &w, double arena)
{
	std::mt19937_64 rng(kSeed);
	auto uniform = [&rng] { return (double)(rng() >> 11) * 0x1p-53; };
	size_t cells = (size_t)std::ceil(std::sqrt((double)kCount));
	double pitch = arena / (double)cells;
	double slack = (pitch - kSize * M_SQRT2) / 2;
	for (size_t i = 0; i < kCount; i++) {
		double cx = -arena / 2 + ((double)(i % cells) + 0.5) * pitch;
		double x = cx + slack * (2 * uniform() - 1);
		double cy = -arena / 2 + ((double)(i / cells) + 0.5) * pitch;
		double y = cy + slack * (2 * uniform() - 1);
		dMatrix3 R;
		dRFromAxisAndAngle(R, 0, 0, 1, 2 * M_PI * uniform());
		dBodySetRotation(w.bodies[i], R);
		dBodySetPosition(w.bodies[i], x, y, kSize / 2);
		double dir = 2 * M_PI * uniform();
		double v = kSpeed * uniform();
		dBodySetLinearVel(w.bodies[i], v * std::cos(dir), v * std::sin(dir), 0);
	}
}

inline void boxes_create(Boxes &w)
{
	w.world = dWorldCreate();
	w.space = dHashSpaceCreate(nullptr);
	w.contacts = dJointGroupCreate(0);
	dWorldSetGravity(w.world, 0, 0, -kGravity);
	dWorldSetCFM(w.world, 1e-5);
	dWorldSetContactSurfaceLayer(w.world, 0.001);
	// ERP, quickstep iterations and SOR, auto-disable: ODE's defaults,
	// which the model keeps too.
	int level = (int)std::floor(std::log2(kSize));
	dHashSpaceSetLevels(w.space, level - 1, level + 3);

	// A tenth of the floor covered, inside a floor and four walls.
	double arena = kSize * std::sqrt((double)kCount / 0.1);
	dCreatePlane(w.space, 0, 0, 1, 0);
	dCreatePlane(w.space, 1, 0, 0, -arena / 2);
	dCreatePlane(w.space, -1, 0, 0, -arena / 2);
	dCreatePlane(w.space, 0, 1, 0, -arena / 2);
	dCreatePlane(w.space, 0, -1, 0, -arena / 2);

	// Creation order is part of the state: it orders ODE's body and geom
	// lists, so the collision pairs and the solver's rows.
	dMass m;
	dMassSetBox(&m, kDensity, kSize, kSize, kSize);
	for (size_t i = 0; i < kCount; i++) {
		dBodyID b = dBodyCreate(w.world);
		dBodySetMass(b, &m);
		dGeomSetBody(dCreateBox(w.space, kSize, kSize, kSize), b);
		w.bodies.push_back(b);
	}
	boxes_scatter(w, arena);
	// The solver reorders its rows with ODE's one global generator: start
	// it where a fresh process has it, as the plug-in starts each world.
	dRandSetSeed(0);
}

// false when ODE could not allocate the step's memory.
inline bool boxes_step(Boxes &w)
{
	dSpaceCollide(w.space, &w, near_callback);
	int ok = dWorldQuickStep(w.world, kStep);
	dJointGroupEmpty(w.contacts);
	return ok != 0;
}

inline void boxes_destroy(Boxes &w)
{
	dJointGroupDestroy(w.contacts);
	dSpaceDestroy(w.space);
	dWorldDestroy(w.world);
	w = Boxes{};
}

// FNV-1a over the bytes of the doubles: equal states, bit for bit, give
// equal sums. Used on both sides, over each box's pose then twist.
inline uint64_t fnv1a(uint64_t h, const double *v, size_t n)
{
	unsigned char bytes[sizeof(double)];
	for (size_t i = 0; i < n; i++) {
		memcpy(bytes, &v[i], sizeof bytes);
		for (unsigned char c : bytes)
			h = (h ^ c) * 0x100000001b3ull;
	}
	return h;
}

constexpr uint64_t kFnvBasis = 0xcbf29ce484222325ull;

// x y z qw qx qy qz, then vx vy vz wx wy wz: the plug-in's pose and twist.
inline uint64_t boxes_checksum(const Boxes &w)
{
	uint64_t h = kFnvBasis;
	for (dBodyID b : w.bodies) {
		const dReal *p = dBodyGetPosition(b), *q = dBodyGetQuaternion(b);
		const dReal *v = dBodyGetLinearVel(b), *a = dBodyGetAngularVel(b);
		double pose[7] = { p[0], p[1], p[2], q[0], q[1], q[2], q[3] };
		double twist[6] = { v[0], v[1], v[2], a[0], a[1], a[2] };
		h = fnv1a(fnv1a(h, pose, 7), twist, 6);
	}
	return h;
}

} // namespace plain
