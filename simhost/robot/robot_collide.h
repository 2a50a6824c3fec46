// A robot's collision geometry: ODE geoms on its link bodies (or fixed in
// the world for welded links) in one space, the contact joints of a step,
// the contact forces on the links a contact sensor watches, and rays cast
// against the geometry for ray sensors.
//
// Which links may touch follows Gazebo's rule: two links of one model (a
// group) collide only when both have self_collide set, two of different
// models (a world file's) always, and never two a joint joins. With no
// such pair the model does no collision work at all.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <set>
#include <utility>
#include <vector>

#include <ode/ode.h>

#include "description.h"
#include "robot_links.h"

namespace tcs::sim::robot {

class Collider {
public:
	Collider(dWorldID world, size_t nlinks);
	~Collider();
	Collider(const Collider &) = delete;
	Collider &operator=(const Collider &) = delete;

	// Adds a link's collisions, with its body in the pose the description
	// gives (the geoms then follow the body wherever it moves).
	void add_link(size_t index, const Link &desc, const RobotLink &link, const Pose &model_in_world);
	// Links joined by a joint never collide.
	void join(size_t a, size_t b);
	// A contact sensor wants the forces on this link.
	void sense(size_t link) { sensed_[link] = true; }
	// After the last add_link and join: whether any pair may collide.
	void finish();
	bool active() const { return active_; }

	// Before a step: contact joints for the pairs that touch. Returns how
	// many contact points there are.
	size_t collide();
	// After the step: the sensed links' contact forces, and the contact
	// joints dropped.
	void after_step();
	uint32_t contact_count(size_t link) const { return counts_[link]; }
	Vec3 contact_force(size_t link) const { return forces_[link]; }

	// The distance to the nearest geom (not of link `exclude`) along the
	// ray, or infinity.
	double cast(dGeomID ray, size_t exclude) const;

private:
	struct GeomInfo {
		size_t link;
		double mu;
		bool self_collide;
		bool moving; // on a body
		int group;
	};
	struct Sensed {
		dJointFeedback fb;
		size_t link1, link2; // the links of body1 and body2
		bool welded2; // link2 has no body: it bears -f1
	};

	static void near(void *data, dGeomID a, dGeomID b);
	bool may_collide(const GeomInfo &a, const GeomInfo &b) const;

	dWorldID world_;
	dSpaceID space_;
	dJointGroupID contacts_;
	std::deque<GeomInfo> infos_; // stable: geoms point at them
	std::vector<dTriMeshDataID> meshes_;
	std::deque<std::vector<double>> mesh_vertices_; // ODE keeps pointers into these
	std::deque<std::vector<dTriIndex>> mesh_indices_;
	std::set<std::pair<size_t, size_t>> joined_;
	std::vector<bool> sensed_;
	std::vector<bool> has_geoms_, self_collide_, moving_;
	std::vector<int> groups_;
	std::deque<Sensed> feedback_; // this step's contacts on sensed links
	std::vector<uint32_t> counts_;
	std::vector<Vec3> forces_;
	bool active_ = false;
};

} // namespace tcs::sim::robot
