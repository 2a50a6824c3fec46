// Geoms from collision shapes, the near callback that filters pairs and
// makes contact joints, contact forces from joint feedback, and ray casts.
#include "robot_collide.h"

#include <algorithm>
#include <cmath>

#include "frames.h"

namespace tcs::sim::robot {

namespace {

constexpr int kMaxContacts = 16; // box-box gives up to 8; meshes more
// Contacts a little soft: with ERP 0.2 and CFM 1e-5 (at a 1 ms step) a
// contact is a spring of 2e7 N/m, overdamped, so a resting body sinks a
// micron or so, stays in contact (no chatter) and bears its weight. No
// surface layer: within one, only the CFM acts, and a body creeps down
// through it at CFM * force (0.2 mm/s for 2 kg on one contact).
constexpr double kContactErp = 0.2;
constexpr double kContactCfm = 1e-5;
constexpr double kSurfaceLayer = 0;

struct RayHit {
	dGeomID ray;
	size_t exclude;
	double nearest;
};

} // namespace

Collider::Collider(dWorldID world, size_t nlinks)
	: world_(world), space_(dHashSpaceCreate(nullptr)), contacts_(dJointGroupCreate(0)), sensed_(nlinks, false),
	  has_geoms_(nlinks, false), self_collide_(nlinks, false), moving_(nlinks, false), groups_(nlinks, 0), counts_(nlinks, 0),
	  forces_(nlinks, Vec3{ 0, 0, 0 })
{
	dWorldSetContactSurfaceLayer(world_, kSurfaceLayer);
}

Collider::~Collider()
{
	dJointGroupDestroy(contacts_);
	dSpaceDestroy(space_); // and its geoms, before the mesh data they use
	for (dTriMeshDataID m : meshes_)
		dGeomTriMeshDataDestroy(m);
}

void Collider::add_link(size_t index, const Link &desc, const RobotLink &link, const Pose &model_in_world)
{
	for (const Collision &c : desc.collisions) {
		Pose at{ c.pose.p, normalized(c.pose.q) };
		at = compose(model_in_world, at);
		const Shape &s = c.shape;
		dGeomID g = nullptr;
		switch (s.kind) {
		case Shape::Kind::box:
			g = dCreateBox(space_, s.size[0], s.size[1], s.size[2]);
			break;
		case Shape::Kind::cylinder:
			g = dCreateCylinder(space_, s.radius, s.length);
			break;
		case Shape::Kind::sphere:
			g = dCreateSphere(space_, s.radius);
			break;
		case Shape::Kind::capsule:
			g = dCreateCapsule(space_, s.radius, s.length);
			break;
		case Shape::Kind::plane: {
			// Not placeable: ODE's plane is n.x = d in the world
			// (robot_check allows planes on welded links only).
			Vec3 n = normalized(rotate(at.q, s.normal));
			g = dCreatePlane(space_, n[0], n[1], n[2], dot(n, at.p));
			break;
		}
		case Shape::Kind::mesh: {
			std::vector<double> &v = mesh_vertices_.emplace_back();
			v.reserve(3 * s.vertices.size());
			for (const Vec3 &p : s.vertices)
				v.insert(v.end(), p.begin(), p.end());
			std::vector<dTriIndex> &ix = mesh_indices_.emplace_back(s.indices.begin(), s.indices.end());
			dTriMeshDataID data = dGeomTriMeshDataCreate();
			meshes_.push_back(data);
			dGeomTriMeshDataBuildDouble(data, v.data(), 3 * sizeof(double), (int)s.vertices.size(),
						    ix.data(), (int)ix.size(), 3 * sizeof(dTriIndex));
			g = dCreateTriMesh(space_, data, nullptr, nullptr, nullptr);
			break;
		}
		}
		if (s.kind != Shape::Kind::plane) {
			dQuaternion q;
			to_ode(at.q, q);
			if (link.body) {
				dGeomSetBody(g, link.body);
				dGeomSetOffsetWorldPosition(g, at.p[0], at.p[1], at.p[2]);
				dGeomSetOffsetWorldQuaternion(g, q);
			} else {
				dGeomSetPosition(g, at.p[0], at.p[1], at.p[2]);
				dGeomSetQuaternion(g, q);
			}
		}
		GeomInfo &info = infos_.emplace_back(GeomInfo{ index, c.mu, desc.self_collide, link.body != nullptr, desc.group });
		dGeomSetData(g, &info);
		has_geoms_[index] = true;
	}
	self_collide_[index] = desc.self_collide;
	moving_[index] = link.body != nullptr;
	groups_[index] = desc.group;
}

void Collider::join(size_t a, size_t b)
{
	joined_.insert({ std::min(a, b), std::max(a, b) });
}

bool Collider::may_collide(const GeomInfo &a, const GeomInfo &b) const
{
	if (a.link == b.link || (!a.moving && !b.moving))
		return false;
	if (a.group == b.group && (!a.self_collide || !b.self_collide))
		return false;
	return !joined_.count({ std::min(a.link, b.link), std::max(a.link, b.link) });
}

void Collider::finish()
{
	// Links of several groups (a world's models) may touch each other.
	std::vector<size_t> candidates;
	bool groups = false;
	for (size_t l = 0; l < has_geoms_.size(); l++)
		if (has_geoms_[l]) {
			groups |= groups_[l] != groups_[0];
			if (self_collide_[l])
				candidates.push_back(l);
		}
	if (groups) {
		active_ = true;
		return;
	}
	active_ = false;
	// Quadratic, but only over self-colliding links; past a few thousand
	// some pair surely may collide.
	if (candidates.size() > 2000) {
		active_ = true;
		return;
	}
	for (size_t i = 0; i < candidates.size() && !active_; i++)
		for (size_t j = i + 1; j < candidates.size() && !active_; j++) {
			GeomInfo a{ candidates[i], 0, true, moving_[candidates[i]], 0 };
			GeomInfo b{ candidates[j], 0, true, moving_[candidates[j]], 0 };
			active_ = may_collide(a, b);
		}
}

void Collider::near(void *data, dGeomID a, dGeomID b)
{
	Collider *self = static_cast<Collider *>(data);
	const GeomInfo *ia = static_cast<const GeomInfo *>(dGeomGetData(a));
	const GeomInfo *ib = static_cast<const GeomInfo *>(dGeomGetData(b));
	if (!self->may_collide(*ia, *ib))
		return;
	// The moving geom first: a contact joint's body1 is then never null,
	// and its feedback's f1 is the force on that body.
	if (!ia->moving) {
		std::swap(a, b);
		std::swap(ia, ib);
	}
	dContact c[kMaxContacts];
	int n = dCollide(a, b, kMaxContacts, &c[0].geom, sizeof c[0]);
	if (n <= 0)
		return;
	dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
	bool sensed = self->sensed_[ia->link] || self->sensed_[ib->link];
	for (int i = 0; i < n; i++) {
		c[i].surface.mode = dContactApprox1 | dContactSoftERP | dContactSoftCFM;
		// Gazebo's rule for two surfaces' friction: the smaller.
		c[i].surface.mu = std::min(ia->mu, ib->mu);
		c[i].surface.soft_erp = kContactErp;
		c[i].surface.soft_cfm = kContactCfm;
		dJointID j = dJointCreateContact(self->world_, self->contacts_, &c[i]);
		dJointAttach(j, ba, bb);
		if (sensed) {
			Sensed &s = self->feedback_.emplace_back();
			s.link1 = ia->link;
			s.link2 = ib->link;
			s.welded2 = bb == nullptr;
			dJointSetFeedback(j, &s.fb);
		}
	}
	self->counts_[ia->link] += (uint32_t)n;
	self->counts_[ib->link] += (uint32_t)n;
}

size_t Collider::collide()
{
	std::fill(counts_.begin(), counts_.end(), 0);
	if (!active_)
		return 0;
	dSpaceCollide(space_, this, &Collider::near);
	size_t n = 0;
	for (uint32_t c : counts_)
		n += c;
	return n / 2; // each contact counted on both links
}

void Collider::after_step()
{
	std::fill(forces_.begin(), forces_.end(), Vec3{ 0, 0, 0 });
	for (const Sensed &s : feedback_) {
		Vec3 f1 = to_vec(s.fb.f1);
		forces_[s.link1] = add(forces_[s.link1], f1);
		// ODE gives no f2 without a body: the reaction, then.
		forces_[s.link2] = add(forces_[s.link2], s.welded2 ? scale(f1, -1) : to_vec(s.fb.f2));
	}
	feedback_.clear();
	dJointGroupEmpty(contacts_);
}

double Collider::cast(dGeomID ray, size_t exclude) const
{
	RayHit hit{ ray, exclude, INFINITY };
	auto cb = [](void *data, dGeomID a, dGeomID b) {
		RayHit *h = static_cast<RayHit *>(data);
		dGeomID other = a == h->ray ? b : a;
		const GeomInfo *info = static_cast<const GeomInfo *>(dGeomGetData(other));
		if (info && info->link == h->exclude)
			return;
		dContactGeom c;
		if (dCollide(h->ray, other, 1, &c, sizeof c) > 0)
			h->nearest = std::min(h->nearest, (double)c.depth);
	};
	dSpaceCollide2(ray, (dGeomID)space_, &hit, cb);
	return hit.nearest;
}

} // namespace tcs::sim::robot
