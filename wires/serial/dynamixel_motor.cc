// The XM430-W350's motor (see dynamixel_motor.h).
#include "dynamixel_motor.h"

namespace tcs {

double dxl_motor_current(double volts, double w, double damping)
{
	return (volts - kDxlKe * w * damping) / kDxlResistance;
}

} // namespace tcs
