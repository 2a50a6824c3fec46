/* The scenario's CAN interfaces as the program sees them (can_ifaces.c):
 * names and indexes come from the device table, where the k-th
 * TCS_DEVICE_CAN entry is interface TCS_CAN_IFINDEX_BASE + k. */
#ifndef TCS_CAN_IFACES_H
#define TCS_CAN_IFACES_H

#include <stdint.h>

#include "runtime.h"

/* The device index of the first CAN interface, or -1 (none, or tcs not
 * active). */
int tcs_can_first_device(void) TCS_HIDDEN;
/* The ifindex of interface name, or 0 when it is not one of ours. */
int32_t tcs_can_ifindex(const char *name) TCS_HIDDEN;
/* The name of one of our ifindexes, or NULL. */
const char *tcs_can_ifname(int32_t ifindex) TCS_HIDDEN;
/* The MTU of one of our ifindexes (16, or 72 for CAN FD), or 0. */
uint32_t tcs_can_mtu(int32_t ifindex) TCS_HIDDEN;
/* The interface ioctls (SIOCGIFINDEX, SIOCGIFNAME, SIOCGIFMTU,
 * SIOCGIFFLAGS) on any fd: 0 or -errno when they name one of our
 * interfaces, 1 when they do not (the kernel answers). */
long tcs_can_if_ioctl(unsigned long request, void *arg) TCS_HIDDEN;

#endif
