/* Opening a device (device_open.h). The one place that knows which kind of
 * fd each kind of device in the table is: above every kind, it hands the
 * new fd to the kind's operations, which set up its state and its entry in
 * the fd table. */
#include "device_open.h"

#include <fcntl.h>

#include "can.h"
#include "device_requests.h"
#include "devices.h"
#include "i2c.h"
#include "raw_syscall.h"
#include "serial.h"

/* Each device kind's operations (enum tcs_device_kind). */
static const struct tcs_fd_ops *const tcs_device_kinds[] = {
	[TCS_DEVICE_SENSOR] = &tcs_sensor_ops,
	[TCS_DEVICE_ACTUATOR] = &tcs_actuator_ops,
	[TCS_DEVICE_SERIAL] = &tcs_serial_ops,
	[TCS_DEVICE_I2C] = &tcs_i2c_ops,
	[TCS_DEVICE_CAN] = &tcs_can_ops,
};

int tcs_device_lookup(const char *path)
{
	if (!tcs_active() || !path || path[0] != '/' || !tcs_rt.devices)
		return -1;
	const struct tcs_device_table *t = tcs_rt.devices;
	for (uint32_t i = 0; i < t->count && i < TCS_MAX_DEVICES; i++)
		if (tcs_str_equal(t->dev[i].path, path))
			return (int)i;
	return -1;
}

long tcs_device_open(int dev, int oflags)
{
	uint32_t kind = tcs_rt.devices->dev[dev].kind;
	const struct tcs_fd_ops *ops =
		kind < sizeof tcs_device_kinds / sizeof *tcs_device_kinds ? tcs_device_kinds[kind] : NULL;
	if (!ops)
		return -ENODEV;
	if (!(ops->access & (1u << (oflags & O_ACCMODE))))
		return -EACCES;
	int handle;
	long fd = tcs_device_request_open((unsigned)dev, oflags, &handle);
	if (fd < 0)
		return fd;
	long r = ops->opened((int)fd, handle, (unsigned)dev);
	if (r < 0) {
		tcs_sys1(SYS_close, fd);
		return r;
	}
	return fd;
}
