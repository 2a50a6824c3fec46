/* A SocketCAN socket's fd in the preload (can.c): socket(PF_CAN, SOCK_RAW,
 * CAN_RAW) opens the scenario's CAN bus as a wire (tcs/wire_protocol.h);
 * bind, the CAN_RAW options, sendmsg and recvmsg speak to the coordinator,
 * which times every frame on its interface. The interfaces' names and
 * indexes come from the device table: the k-th TCS_DEVICE_CAN entry is
 * interface TCS_CAN_IFINDEX_BASE + k. */
#ifndef TCS_CAN_H
#define TCS_CAN_H

#include <stddef.h>
#include <stdint.h>

#include "runtime.h"
#include "wire_fds.h"

struct msghdr;
struct sockaddr;

/* A new CAN fd's state: unbound, loopback on. */
void tcs_can_opened(struct tcs_wire_fd *w) TCS_HIDDEN;
/* The device index of the first CAN interface, or -1 (none, or tcs not
 * active). */
int tcs_can_first_device(void) TCS_HIDDEN;
/* The ifindex of interface name, or 0 when it is not one of ours. */
int32_t tcs_can_ifindex(const char *name) TCS_HIDDEN;
/* The name of one of our ifindexes, or NULL. */
const char *tcs_can_ifname(int32_t ifindex) TCS_HIDDEN;
/* The MTU of one of our ifindexes (16, or 72 for CAN FD), or 0. */
uint32_t tcs_can_mtu(int32_t ifindex) TCS_HIDDEN;

/* bind(2) of CAN fd (device handle h): 0 or -errno. */
long tcs_can_bind(int fd, int h, const struct sockaddr *addr, uint32_t len) TCS_HIDDEN;
long tcs_can_getsockname(int fd, struct sockaddr *addr, uint32_t *len) TCS_HIDDEN;
long tcs_can_setsockopt(int fd, int h, int level, int name, const void *value, uint32_t len) TCS_HIDDEN;
long tcs_can_getsockopt(int fd, int level, int name, void *value, uint32_t *len) TCS_HIDDEN;
/* recvmsg(2) and sendmsg(2) of CAN fd: the result or -errno. read, recv,
 * recvfrom and readv are recvmsg; write, send, sendto and writev sendmsg. */
long tcs_can_recvmsg(int fd, int h, struct msghdr *msg, int flags) TCS_HIDDEN;
long tcs_can_sendmsg(int fd, int h, const struct msghdr *msg, int flags) TCS_HIDDEN;
/* ioctl(2) of CAN fd: SIOCGSTAMP, SIOCGSTAMPNS, FIONREAD; -ENOTTY else. */
long tcs_can_ioctl(int fd, int h, unsigned long request, void *arg) TCS_HIDDEN;
/* The interface ioctls (SIOCGIFINDEX, SIOCGIFNAME, SIOCGIFMTU,
 * SIOCGIFFLAGS) on any fd: 0 or -errno when they name one of our
 * interfaces, 1 when they do not (the kernel answers). */
long tcs_can_if_ioctl(unsigned long request, void *arg) TCS_HIDDEN;

#endif
