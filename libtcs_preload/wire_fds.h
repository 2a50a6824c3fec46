/* What the preload keeps of each wire fd (wire_fds.c): the line settings a
 * tty shows, the address an I2C fd talks to, a CAN socket's options that
 * shape what it reads. The coordinator keeps what decides timing. */
#ifndef TCS_WIRE_FDS_H
#define TCS_WIRE_FDS_H

#include <stdint.h>
#include <termios.h>

#include "fd_table.h"
#include "runtime.h"

struct tcs_wire_fd {
	struct termios tio;  /* serial: as tcgetattr shows it */
	uint32_t baud;       /* serial: the line's rate, also where c_cflag cannot say it (BOTHER) */
	uint32_t modem;      /* serial: the TIOCM_* lines TIOCMGET shows (TIOCMSET/BIS/BIC set DTR, RTS) */
	uint16_t i2c_addr;   /* I2C: I2C_SLAVE's; 0xffff: none set */
	uint8_t i2c_tenbit;  /* I2C: I2C_TENBIT */
	uint8_t can_fd_frames; /* CAN: CAN_RAW_FD_FRAMES */
	uint8_t can_stamp;     /* CAN: 0, or SO_TIMESTAMP, SO_TIMESTAMPNS (the one reported) */
	/* CAN: what getsockopt, getsockname and the cmsgs of a read show;
	 * the coordinator keeps what decides delivery. */
	uint8_t can_loopback, can_recv_own, can_join, can_rxq_ovfl;
	uint32_t can_err_mask;
	uint32_t can_timestamping; /* SO_TIMESTAMPING's flags */
	int32_t can_ifindex;       /* bound to (0: every interface, or not bound) */
	int64_t can_last_ns;       /* the last frame read's arrival (virtual), -1: none */
};

/* The state of wire fd, or NULL (fd is no wire's). */
struct tcs_wire_fd *tcs_wire_fd(int fd) TCS_HIDDEN;
/* The state of a wire's entry. */
struct tcs_wire_fd *tcs_wire_of(const struct tcs_fd *e) TCS_HIDDEN;
/* A fresh state in a free slot, zeroed but for no I2C address: the slot,
 * or -EMFILE when every one is taken. */
int tcs_wire_slot_new(void) TCS_HIDDEN;
/* Every wire kind's forget and copy (struct tcs_fd_ops): a dup shares the
 * open file, as the kernel's does, so one state for both; the slot is free
 * again when its last fd is closed. */
void tcs_wire_forget(int fd, const struct tcs_fd *e) TCS_HIDDEN;
void tcs_wire_copy(int to, const struct tcs_fd *e) TCS_HIDDEN;

#endif
