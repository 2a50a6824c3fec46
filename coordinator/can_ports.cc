// What a CAN_RAW socket receives, as the kernel decides it (net/can/raw.c
// and af_can.c, read as facts): its binding, its filters, its options;
// and the options themselves, checked as raw_setsockopt checks them.
#include "can_ports.h"

#include <linux/can.h>
#include <linux/can/raw.h>
#include <sys/socket.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "tcs/wire_protocol.h"

namespace tcs {

namespace {

// A frame's can_id as a receiving socket's filters see it: the id with
// CAN_EFF_FLAG and CAN_RTR_FLAG.
uint32_t linux_can_id(const CanFrame &f)
{
	return f.id | (f.extended ? CAN_EFF_FLAG : 0) | (f.rtr && !f.fd ? CAN_RTR_FLAG : 0);
}

// One filter, as af_can.c registers it: the mask keeps the id bits and
// the EFF and RTR flags, the id is taken under the mask; CAN_INV_FILTER
// inverts the match; a mask with CAN_ERR_FLAG is an error-frame filter,
// which no data frame meets (none of ours is an error frame).
bool filter_matches(const CanFilter &flt, uint32_t can_id)
{
	if (flt.mask & CAN_ERR_FLAG)
		return false;
	const uint32_t mask = flt.mask & (CAN_EFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG);
	const bool match = (can_id & mask) == (flt.id & mask);
	return (flt.id & CAN_INV_FILTER) ? !match : match;
}

int64_t int_option(std::string_view value, bool *out)
{
	int v = 0;
	if (value.size() != sizeof v)
		return -EINVAL;
	memcpy(&v, value.data(), sizeof v);
	*out = v != 0;
	return 0;
}

} // namespace

bool can_filters_pass(const WirePort &port, const CanFrame &frame)
{
	const uint32_t id = linux_can_id(frame);
	size_t matched = 0;
	for (const CanFilter &f : port.filters)
		matched += filter_matches(f, id) ? 1 : 0;
	// Joined, every filter must match (raw_rcv counts the matches of one
	// frame); else one is enough, and the frame comes once however many do.
	if (port.join_filters && port.filters.size() > 1)
		return matched == port.filters.size();
	return matched > 0;
}

int64_t can_set_option(WirePort &port, int32_t level, int32_t name, std::string_view value)
{
	if (level != SOL_CAN_RAW)
		return -EINVAL;
	switch (name) {
	case CAN_RAW_FILTER: {
		if (value.size() % sizeof(can_filter) != 0 || value.size() > CAN_RAW_FILTER_MAX * sizeof(can_filter))
			return -EINVAL;
		std::vector<CanFilter> filters(value.size() / sizeof(can_filter));
		for (size_t i = 0; i < filters.size(); i++) {
			can_filter f;
			memcpy(&f, value.data() + i * sizeof f, sizeof f);
			filters[i] = CanFilter{ f.can_id, f.can_mask };
		}
		port.filters = std::move(filters); // (none: it receives nothing)
		return 0;
	}
	case CAN_RAW_ERR_FILTER: {
		can_err_mask_t m = 0;
		if (value.size() != sizeof m)
			return -EINVAL;
		memcpy(&m, value.data(), sizeof m);
		port.err_mask = m & CAN_ERR_MASK;
		return 0;
	}
	case CAN_RAW_LOOPBACK:
		return int_option(value, &port.loopback);
	case CAN_RAW_RECV_OWN_MSGS:
		return int_option(value, &port.recv_own);
	case CAN_RAW_FD_FRAMES:
		return int_option(value, &port.fd_frames);
	case CAN_RAW_JOIN_FILTERS:
		return int_option(value, &port.join_filters);
	default: // (CAN XL's options too: no interface of ours is an XL one)
		return -ENOPROTOOPT;
	}
}

// The frame d that has ended on its interface to every socket that receives it (as
// can_send's loopback and raw_rcv decide): bound to f or to every
// interface; the sender's own socket only with CAN_RAW_RECV_OWN_MSGS, and
// another local one only when the sender had CAN_RAW_LOOPBACK on; an FD
// frame only where CAN_RAW_FD_FRAMES is; past the socket's filters.
void can_deliver(const std::vector<std::weak_ptr<WirePort>> &ports, int32_t ifindex, const CanDelivery &d,
		 bool loopback)
{
	const bool from_socket = d.source < kCanWorldSources;
	const size_t size = linux_frame_size(d.frame);
	for (const auto &wp : ports) {
		auto p = wp.lock();
		if (!p || p->gone || (p->ifindex != 0 && p->ifindex != ifindex))
			continue;
		const bool own = from_socket && p->can_source == d.source;
		if (from_socket && (!loopback || (own && !p->recv_own)))
			continue;
		if (d.frame.fd && !p->fd_frames)
			continue;
		if (!can_filters_pass(*p, d.frame))
			continue;
		// (drops: stamped as it goes into the socket, device_server.cc)
		tcs_wire_can_rx head{ d.end_ns, ifindex,
				      from_socket ? (TCS_CAN_RX_LOCAL | (own ? TCS_CAN_RX_OWN : 0u)) : 0u, 0, 0 };
		std::string packet(reinterpret_cast<const char *>(&head), sizeof head);
		packet.resize(sizeof head + size);
		frame_to_linux(d.frame, packet.data() + sizeof head, size);
		p->push(d.end_ns, std::move(packet));
	}
}

} // namespace tcs
