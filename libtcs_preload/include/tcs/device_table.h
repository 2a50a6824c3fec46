/* The device table: which paths are virtual devices, published by the
 * coordinator in the shared region beside the clock page, written once
 * before the controller starts and constant afterwards. The preload
 * matches a path in open()/fopen() against it without a round trip. */
#ifndef TCS_DEVICE_TABLE_H
#define TCS_DEVICE_TABLE_H

#include <stdint.h>

#include "clock_page.h"
#include "protocol.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TCS_DEVICE_PATH_MAX 256

enum tcs_device_kind {
	TCS_DEVICE_SENSOR = 1,   /* the controller reads records */
	TCS_DEVICE_ACTUATOR = 2, /* the controller writes records */
	/* The robot's wires (tcs/wire_protocol.h): read and written both ways. */
	TCS_DEVICE_SERIAL = 3, /* a tty: path is its device file */
	TCS_DEVICE_I2C = 4,    /* /dev/i2c-N */
	TCS_DEVICE_CAN = 5,    /* a SocketCAN interface: path is its name ("can0"), never opened by path */
};

enum tcs_device_format {
	TCS_FORMAT_TEXT = 1,   /* numbers separated by spaces, one line per record */
	TCS_FORMAT_BINARY = 2, /* little-endian f64 per signal */
};

struct tcs_device_entry {
	char path[TCS_DEVICE_PATH_MAX]; /* absolute, NUL-terminated */
	uint32_t kind;                  /* enum tcs_device_kind */
	uint32_t format;                /* enum tcs_device_format */
	uint32_t latest;                /* sensor: every read is answered with the world now */
	uint32_t width;                 /* values per record; a CAN interface's MTU (16, or 72 for FD) */
};

struct tcs_device_table {
	uint32_t count;
	uint32_t reserved;
	struct tcs_device_entry dev[TCS_MAX_DEVICES];
};

/* The shared region: the clock page, then the device table. */
#define TCS_DEVICE_TABLE_OFFSET TCS_PAGE_SIZE
#define TCS_SHARED_SIZE (TCS_PAGE_SIZE + 5 * TCS_PAGE_SIZE)

#if defined(__cplusplus)
static_assert(sizeof(struct tcs_device_table) <= TCS_SHARED_SIZE - TCS_DEVICE_TABLE_OFFSET, "table too large");
#else
_Static_assert(sizeof(struct tcs_device_table) <= TCS_SHARED_SIZE - TCS_DEVICE_TABLE_OFFSET, "table too large");
#endif

static inline struct tcs_device_table *tcs_device_table_of(void *shared)
{
	return (struct tcs_device_table *)((char *)shared + TCS_DEVICE_TABLE_OFFSET);
}

#ifdef __cplusplus
}
#endif
#endif
