// Rigid transforms on the description's plain types (robot::Vec3, Quat,
// Pose), and their conversion to ODE's: the robot model places every body,
// geom, joint and sensor by composing the poses the description gives in
// the model's frame with the model's pose in the world.
#pragma once

#include <cmath>

#include <ode/ode.h>

#include "description.h"

namespace tcs::sim::robot {

inline Vec3 add(const Vec3 &a, const Vec3 &b)
{
	return { a[0] + b[0], a[1] + b[1], a[2] + b[2] };
}

inline Vec3 sub(const Vec3 &a, const Vec3 &b)
{
	return { a[0] - b[0], a[1] - b[1], a[2] - b[2] };
}

inline Vec3 scale(const Vec3 &a, double s)
{
	return { a[0] * s, a[1] * s, a[2] * s };
}

inline double dot(const Vec3 &a, const Vec3 &b)
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

inline Vec3 cross(const Vec3 &a, const Vec3 &b)
{
	return { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
}

inline double norm(const Vec3 &a)
{
	return std::sqrt(dot(a, a));
}

inline Quat qmul(const Quat &a, const Quat &b)
{
	return { a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
		 a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
		 a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
		 a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0] };
}

inline Quat conj(const Quat &q)
{
	return { q[0], -q[1], -q[2], -q[3] };
}

// The vector v rotated by the unit quaternion q.
inline Vec3 rotate(const Quat &q, const Vec3 &v)
{
	Vec3 u{ q[1], q[2], q[3] };
	Vec3 t = scale(cross(u, v), 2);
	return add(add(v, scale(t, q[0])), cross(u, t));
}

// The vector v, given in the world, in the frame rotated by q.
inline Vec3 unrotate(const Quat &q, const Vec3 &v)
{
	return rotate(conj(q), v);
}

// a ∘ b: b given in a's frame, returned in the frame a is given in.
inline Pose compose(const Pose &a, const Pose &b)
{
	return { add(a.p, rotate(a.q, b.p)), qmul(a.q, b.q) };
}

inline Pose inverse(const Pose &a)
{
	Quat c = conj(a.q);
	return { rotate(c, scale(a.p, -1)), c };
}

// The quaternion scaled to unit length (descriptions written by hand or
// rounded in a file are close to unit, not exactly).
inline Quat normalized(const Quat &q)
{
	double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
	return { q[0] / n, q[1] / n, q[2] / n, q[3] / n };
}

inline Vec3 normalized(const Vec3 &v)
{
	return scale(v, 1 / norm(v));
}

inline Vec3 to_vec(const dReal *v)
{
	return { v[0], v[1], v[2] };
}

inline Quat to_quat(const dReal *q)
{
	return { q[0], q[1], q[2], q[3] };
}

inline void to_ode(const Quat &q, dQuaternion out)
{
	for (int i = 0; i < 4; i++)
		out[i] = q[i];
}

// The rotation matrix of a unit quaternion, as ODE lays it out.
inline void to_ode_matrix(const Quat &q, dMatrix3 out)
{
	dQuaternion oq;
	to_ode(q, oq);
	dQtoR(oq, out);
}

} // namespace tcs::sim::robot
