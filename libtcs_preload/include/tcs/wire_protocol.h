/* What goes through a wire's fd (docs/DESIGN.md §9): a serial line, an I2C
 * bus or a CAN socket is, to the controller, a real socket whose other end
 * the coordinator holds, as a device's is (device_table.h). The preload
 * writes packets, each a tcs_wire_head and its payload, and then asks the
 * coordinator to take them (DEV_SYNC WRITE, answered with 0 or -errno);
 * the coordinator puts in what arrives, when it is due in virtual time:
 * a serial line's bytes as they are (a stream socket), a CAN frame or an
 * I2C transfer's answer as one packet (a seqpacket socket). Everything the
 * preload writes is untrusted: the coordinator checks every field. */
#ifndef TCS_WIRE_PROTOCOL_H
#define TCS_WIRE_PROTOCOL_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* A packet's payload is at most this (a CAN FD frame, an I2C transfer of
 * I2C_RDWR's 42 messages is far less; serial writes are cut to it): the
 * largest is CAN_RAW_FILTER's 512 filters (4096 bytes) and their option's
 * head. */
#define TCS_WIRE_PAYLOAD_MAX (4096 + 8)

enum tcs_wire_type {
	TCS_WIRE_DATA = 1,   /* serial: bytes to send; CAN: one frame, 16 or 72 bytes */
	TCS_WIRE_LINE = 2,   /* serial: struct tcs_wire_line, the line's new settings */
	TCS_WIRE_BIND = 3,   /* CAN: int32 ifindex (0: every interface) */
	TCS_WIRE_CANOPT = 4, /* CAN: struct tcs_wire_canopt, then the option's value */
	TCS_WIRE_XFER = 5,   /* I2C: u32 count, count tcs_wire_i2c_msg, then the bytes written */
	TCS_WIRE_SMBUS = 6,  /* I2C: struct tcs_wire_smbus */
};

struct tcs_wire_head {
	uint32_t type; /* enum tcs_wire_type */
	uint32_t len;  /* payload bytes that follow */
};

struct tcs_wire_line {
	uint32_t baud;          /* bit/s */
	uint32_t bits_per_byte; /* start, data, parity and stop bits: 10 for 8N1 */
};

struct tcs_wire_canopt {
	int32_t level; /* SOL_CAN_RAW or SOL_SOCKET */
	int32_t name;
};

struct tcs_wire_i2c_msg {
	uint16_t addr;
	uint16_t flags; /* I2C_M_* */
	uint16_t len;
	uint16_t reserved;
};

struct tcs_wire_smbus {
	uint16_t addr;
	uint8_t read_write, command;
	uint32_t size;     /* I2C_SMBUS_* */
	uint8_t data[34];  /* union i2c_smbus_data */
	uint8_t reserved[2];
};

/* What the coordinator puts in a CAN socket: this, then the frame (16
 * bytes, or 72 for an FD frame on a socket that takes them). */
struct tcs_wire_can_rx {
	int64_t t_ns;    /* virtual CLOCK_MONOTONIC when it arrived */
	int32_t ifindex; /* the interface it came on */
	uint32_t flags;  /* TCS_CAN_RX_* */
	uint32_t drops;  /* frames the socket had dropped when this one was queued (SO_RXQ_OVFL) */
	uint32_t reserved;
};
#define TCS_CAN_RX_LOCAL 1u /* sent from this machine (MSG_DONTROUTE) */
#define TCS_CAN_RX_OWN 2u   /* sent from this socket (MSG_CONFIRM) */

/* What the coordinator puts in an I2C fd after a transfer: this, then the
 * bytes read (XFER: every read message's, in order; SMBUS: the union). */
struct tcs_wire_i2c_reply {
	int32_t result; /* messages done, 0, or -errno */
	uint32_t len;
};

/* A CAN interface's ifindex: beyond any real one's (the table's index
 * added). */
#define TCS_CAN_IFINDEX_BASE 0x7c000000

#ifdef __cplusplus
}
#endif

#endif
