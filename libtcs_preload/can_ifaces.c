/* The CAN interfaces (see can_ifaces.h): answered from the device table,
 * for any socket's ioctls and if_nametoindex (the kernel has no such
 * interfaces: `ip link` and netlink do not see them). */
#include "can_ifaces.h"

#include <linux/sockios.h>
#include <net/if.h>
#include <string.h>
#include <sys/ioctl.h>

#include "tcs/wire_protocol.h"

/* The k-th CAN entry of the device table, or NULL. */
static const struct tcs_device_entry *tcs_can_entry(int32_t k, int *dev)
{
	if (!tcs_active() || !tcs_rt.devices || k < 0)
		return NULL;
	const struct tcs_device_table *t = tcs_rt.devices;
	for (uint32_t i = 0; i < t->count && i < TCS_MAX_DEVICES; i++)
		if (t->dev[i].kind == TCS_DEVICE_CAN && k-- == 0) {
			if (dev)
				*dev = (int)i;
			return &t->dev[i];
		}
	return NULL;
}

int tcs_can_first_device(void)
{
	int dev = -1;
	return tcs_can_entry(0, &dev) ? dev : -1;
}

int32_t tcs_can_ifindex(const char *name)
{
	const struct tcs_device_entry *e;
	for (int32_t k = 0; name && (e = tcs_can_entry(k, NULL)) != NULL; k++)
		if (tcs_str_equal(e->path, name))
			return TCS_CAN_IFINDEX_BASE + k;
	return 0;
}

const char *tcs_can_ifname(int32_t ifindex)
{
	const struct tcs_device_entry *e = tcs_can_entry(ifindex - TCS_CAN_IFINDEX_BASE, NULL);
	return e ? e->path : NULL;
}

uint32_t tcs_can_mtu(int32_t ifindex)
{
	const struct tcs_device_entry *e = tcs_can_entry(ifindex - TCS_CAN_IFINDEX_BASE, NULL);
	return e ? e->width : 0;
}

long tcs_can_if_ioctl(unsigned long request, void *arg)
{
	if (request != SIOCGIFINDEX && request != SIOCGIFNAME && request != SIOCGIFMTU && request != SIOCGIFFLAGS)
		return 1;
	if (!tcs_active() || tcs_can_first_device() < 0 || !arg)
		return 1;
	struct ifreq *r = (struct ifreq *)arg;
	if (request == SIOCGIFNAME) {
		const char *name = tcs_can_ifname(r->ifr_ifindex);
		if (!name)
			return 1;
		memset(r->ifr_name, 0, sizeof r->ifr_name);
		size_t len = strnlen(name, sizeof r->ifr_name - 1); /* (the scenario's: at most 15) */
		memcpy(r->ifr_name, name, len);
		return 0;
	}
	char name[IFNAMSIZ];
	memcpy(name, r->ifr_name, sizeof name);
	name[IFNAMSIZ - 1] = 0;
	int32_t ifindex = tcs_can_ifindex(name);
	if (ifindex == 0)
		return 1;
	if (request == SIOCGIFINDEX)
		r->ifr_ifindex = ifindex;
	else if (request == SIOCGIFMTU)
		r->ifr_mtu = (int)tcs_can_mtu(ifindex);
	else
		r->ifr_flags = IFF_UP | IFF_RUNNING | IFF_NOARP;
	return 0;
}
