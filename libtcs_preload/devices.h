/* Record devices in the preload (devices.c): a scenario's sensors, whose
 * fds the controller reads records from, and actuators, to which it writes
 * them, in virtual time. Their operations (fd_table.h) are these two. */
#ifndef TCS_DEVICES_H
#define TCS_DEVICES_H

#include "fd_table.h"
#include "runtime.h"

extern const struct tcs_fd_ops tcs_sensor_ops TCS_HIDDEN;
extern const struct tcs_fd_ops tcs_actuator_ops TCS_HIDDEN;

#endif
