// merge_world (see world_merge.h).
#include "world_merge.h"

#include <set>

#include "frames.h"

namespace tcs::sim::robot {

Model merge_world(const Description &world)
{
	Model out;
	out.name = "world";
	out.where.file = world.file;
	for (size_t g = 0; g < world.models.size(); g++) {
		const Model &m = world.models[g];
		const Pose &at = m.pose;
		const std::string prefix = m.name + ".";
		auto renamed = [&prefix](const std::string &link) { return link == "world" ? link : prefix + link; };
		std::set<std::string> children;
		for (Joint j : m.joints) {
			children.insert(j.child);
			j.name = prefix + j.name;
			j.parent = renamed(j.parent);
			j.child = renamed(j.child);
			j.pose = compose(at, j.pose);
			j.axis = rotate(at.q, j.axis);
			j.axis2 = rotate(at.q, j.axis2);
			out.joints.push_back(std::move(j));
		}
		for (Link l : m.links) {
			if (m.is_static && !children.count(l.name)) {
				// A static model's roots are welded, the rest by their joints.
				Joint weld;
				weld.name = prefix + l.name + ".static";
				weld.kind = Joint::Kind::fixed;
				weld.parent = "world";
				weld.child = prefix + l.name;
				weld.pose = compose(at, l.pose);
				weld.where = l.where;
				out.joints.push_back(std::move(weld));
			}
			l.name = prefix + l.name;
			l.pose = compose(at, l.pose);
			l.inertial = compose(at, l.inertial);
			for (Collision &c : l.collisions)
				c.pose = compose(at, c.pose);
			l.group = (int)g;
			out.links.push_back(std::move(l));
		}
		for (Sensor s : m.sensors) {
			s.name = prefix + s.name;
			s.link = renamed(s.link);
			if (!s.joint.empty())
				s.joint = prefix + s.joint;
			s.pose = compose(at, s.pose);
			out.sensors.push_back(std::move(s));
		}
	}
	return out;
}

} // namespace tcs::sim::robot
