// Pose and twist of ODE bodies for the signals, and rigid placement of a
// body about a hinge (models are built in their zero pose so that ODE's
// joint angles are measured from it, then moved to their initial state).
#include "body_state.h"

#include <cmath>

namespace tcs::sim {

void read_pose(dBodyID body, double out[7])
{
	const dReal *p = dBodyGetPosition(body);
	const dReal *q = dBodyGetQuaternion(body); // ODE's order is w x y z too
	for (int i = 0; i < 3; i++)
		out[i] = p[i];
	for (int i = 0; i < 4; i++)
		out[3 + i] = q[i];
}

void read_twist(dBodyID body, double out[6])
{
	const dReal *v = dBodyGetLinearVel(body);
	const dReal *w = dBodyGetAngularVel(body);
	for (int i = 0; i < 3; i++) {
		out[i] = v[i];
		out[3 + i] = w[i];
	}
}

bool body_finite(dBodyID body)
{
	const dReal *p = dBodyGetPosition(body);
	const dReal *v = dBodyGetLinearVel(body);
	const dReal *w = dBodyGetAngularVel(body);
	for (int i = 0; i < 3; i++)
		if (!std::isfinite(p[i]) || !std::isfinite(v[i]) || !std::isfinite(w[i]))
			return false;
	return true;
}

void place_rotated(dBodyID body, const dVector3 pivot, const dVector3 axis, const dVector3 ref_pos,
		   double angle, double rate)
{
	dMatrix3 R;
	dRFromAxisAndAngle(R, axis[0], axis[1], axis[2], angle);
	dVector3 r0 = { ref_pos[0] - pivot[0], ref_pos[1] - pivot[1], ref_pos[2] - pivot[2], 0 };
	dVector3 r;
	dMultiply0_331(r, R, r0);
	dBodySetRotation(body, R);
	dBodySetPosition(body, pivot[0] + r[0], pivot[1] + r[1], pivot[2] + r[2]);

	dVector3 w = { rate * axis[0], rate * axis[1], rate * axis[2], 0 };
	dVector3 v;
	dCalcVectorCross3(v, w, r);
	dBodySetAngularVel(body, w[0], w[1], w[2]);
	dBodySetLinearVel(body, v[0], v[1], v[2]);
}

void place_at_rest(dBodyID body, const dVector3 pos, const dVector3 axis, double angle)
{
	dMatrix3 R;
	dRFromAxisAndAngle(R, axis[0], axis[1], axis[2], angle);
	dBodySetRotation(body, R);
	dBodySetPosition(body, pos[0], pos[1], pos[2]);
	dBodySetAngularVel(body, 0, 0, 0);
	dBodySetLinearVel(body, 0, 0, 0);
}

} // namespace tcs::sim
