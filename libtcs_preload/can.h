/* A SocketCAN socket's fd in the preload (can.c): socket(PF_CAN, SOCK_RAW,
 * CAN_RAW) opens the scenario's CAN bus as a wire (tcs/wire_protocol.h);
 * bind, the CAN_RAW options, sendmsg and recvmsg speak to the coordinator,
 * which times every frame on its interface. Its operations (fd_table.h):
 * read, recv and recvfrom are recvmsg; write, send and sendto sendmsg;
 * ioctl answers SIOCGSTAMP, SIOCGSTAMPNS, FIONREAD and the interfaces'. */
#ifndef TCS_CAN_H
#define TCS_CAN_H

#include "fd_table.h"
#include "runtime.h"

extern const struct tcs_fd_ops tcs_can_ops TCS_HIDDEN;

#endif
