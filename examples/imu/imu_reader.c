/* An IMU reader as it would run on a robot's Linux board: an InvenSense
 * MPU-6050 on /dev/i2c-1 through i2c-dev, nothing of tcs. It checks
 * WHO_AM_I, wakes the chip, sets its ranges (±4 g, ±500 °/s) and its
 * sample rate (1 kHz with the low-pass filter at 44 Hz), then reads the
 * accelerometer, temperature and gyroscope in one 14-byte burst at a fixed
 * rate and prints them in SI units, one line a sample.
 *
 *     imu_reader [--bus N] [--address 0x68] [--rate HZ] [--count N]
 */
#include <errno.h>
#include <fcntl.h>
#include <linux/i2c-dev.h>
#include <linux/i2c.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <time.h>
#include <unistd.h>

#define REG_SMPLRT_DIV 0x19
#define REG_CONFIG 0x1a
#define REG_GYRO_CONFIG 0x1b
#define REG_ACCEL_CONFIG 0x1c
#define REG_ACCEL_XOUT_H 0x3b
#define REG_PWR_MGMT_1 0x6b
#define REG_WHO_AM_I 0x75

#define G 9.80665
#define ACCEL_LSB_PER_G 8192.0 /* ±4 g */
#define GYRO_LSB_PER_DPS 65.5  /* ±500 °/s */

static int fd;

static int write_reg(uint8_t reg, uint8_t value)
{
	uint8_t b[2] = { reg, value };
	return write(fd, b, 2) == 2 ? 0 : -1;
}

/* Register reg and the n after it, in one combined transfer (a write of
 * the register number, a repeated START, the read). */
static int read_regs(uint8_t address, uint8_t reg, uint8_t *out, uint16_t n)
{
	struct i2c_msg msgs[2] = {
		{ address, 0, 1, &reg },
		{ address, I2C_M_RD, n, out },
	};
	struct i2c_rdwr_ioctl_data d = { msgs, 2 };
	return ioctl(fd, I2C_RDWR, &d) == 2 ? 0 : -1;
}

static int16_t be16(const uint8_t *p)
{
	return (int16_t)((p[0] << 8) | p[1]);
}

int main(int argc, char **argv)
{
	int bus = 1, address = 0x68, count = 10;
	double rate = 100;
	for (int i = 1; i + 1 < argc; i += 2) {
		if (!strcmp(argv[i], "--bus"))
			bus = atoi(argv[i + 1]);
		else if (!strcmp(argv[i], "--address"))
			address = (int)strtol(argv[i + 1], NULL, 0);
		else if (!strcmp(argv[i], "--rate"))
			rate = atof(argv[i + 1]);
		else if (!strcmp(argv[i], "--count"))
			count = atoi(argv[i + 1]);
		else {
			fprintf(stderr, "usage: imu_reader [--bus N] [--address 0x68] [--rate HZ] [--count N]\n");
			return 2;
		}
	}
	char path[32];
	snprintf(path, sizeof path, "/dev/i2c-%d", bus);
	fd = open(path, O_RDWR);
	if (fd < 0) {
		fprintf(stderr, "imu_reader: %s: %s\n", path, strerror(errno));
		return 1;
	}
	uint8_t who = 0;
	if (ioctl(fd, I2C_SLAVE, address) < 0 || read_regs((uint8_t)address, REG_WHO_AM_I, &who, 1) < 0) {
		fprintf(stderr, "imu_reader: no chip at 0x%02x on %s: %s\n", address, path, strerror(errno));
		return 1;
	}
	if (who != 0x68) {
		fprintf(stderr, "imu_reader: WHO_AM_I is 0x%02x, not an MPU-6050's 0x68\n", who);
		return 1;
	}
	/* Out of sleep on the gyroscope's clock; 1 kHz; the chip's own filter. */
	if (write_reg(REG_PWR_MGMT_1, 0x01) < 0 || write_reg(REG_CONFIG, 0x03) < 0 ||
	    write_reg(REG_SMPLRT_DIV, 0x00) < 0 || write_reg(REG_GYRO_CONFIG, 1 << 3) < 0 ||
	    write_reg(REG_ACCEL_CONFIG, 1 << 3) < 0) {
		fprintf(stderr, "imu_reader: setting the chip up: %s\n", strerror(errno));
		return 1;
	}
	/* The gyroscope needs some 30 ms to start (datasheet: start-up time). */
	struct timespec next;
	clock_gettime(CLOCK_MONOTONIC, &next);
	next.tv_nsec += 30000000;
	const long period_ns = (long)(1e9 / rate);
	for (int i = 0; i < count; i++) {
		while (next.tv_nsec >= 1000000000) {
			next.tv_nsec -= 1000000000;
			next.tv_sec++;
		}
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL);
		uint8_t b[14];
		if (read_regs((uint8_t)address, REG_ACCEL_XOUT_H, b, sizeof b) < 0) {
			fprintf(stderr, "imu_reader: reading: %s\n", strerror(errno));
			return 1;
		}
		struct timespec now;
		clock_gettime(CLOCK_MONOTONIC, &now);
		double a[3], w[3];
		for (int k = 0; k < 3; k++) {
			a[k] = be16(b + 2 * k) / ACCEL_LSB_PER_G * G;
			w[k] = be16(b + 8 + 2 * k) / GYRO_LSB_PER_DPS * 3.14159265358979 / 180;
		}
		printf("%ld.%09ld accel %.4f %.4f %.4f m/s^2 gyro %.4f %.4f %.4f rad/s temp %.2f C\n", (long)now.tv_sec,
		       now.tv_nsec, a[0], a[1], a[2], w[0], w[1], w[2], be16(b + 6) / 340.0 + 36.53);
		next.tv_nsec += period_ns;
	}
	return 0;
}
