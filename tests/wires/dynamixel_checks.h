// What the Dynamixel tests share: bytes a controller writes, through the
// parser to a chain, and the replies' bytes back.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <variant>
#include <vector>

#include "dynamixel2_parser.h"
#include "dynamixel_chain.h"

namespace dxl_checks {

using Bytes = std::vector<uint8_t>;

// Everything the controller wrote, parsed, each packet (or fault) handed
// to the chain: the replies in wire order.
inline std::vector<tcs::DxlReply> send(tcs::DynamixelChain &chain, const Bytes &written,
				       std::vector<std::string> *notes = nullptr)
{
	tcs::Dxl2Parser parser;
	parser.feed(written.data(), written.size());
	std::vector<tcs::DxlReply> out;
	tcs::Dxl2Item item;
	while (parser.next(item)) {
		std::vector<tcs::DxlReply> r = std::holds_alternative<tcs::Dxl2Packet>(item)
						       ? chain.handle(std::get<tcs::Dxl2Packet>(item), 0, notes)
						       : chain.handle(std::get<tcs::Dxl2Fault>(item), 0, notes);
		out.insert(out.end(), r.begin(), r.end());
	}
	return out;
}

inline tcs::Dxl2Packet status_of(const tcs::DxlReply &r)
{
	tcs::Dxl2Parser parser;
	parser.feed(r.bytes.data(), r.bytes.size());
	tcs::Dxl2Item item;
	if (!parser.next(item) || !std::holds_alternative<tcs::Dxl2Packet>(item))
		return {};
	return std::get<tcs::Dxl2Packet>(item);
}

inline Bytes write_of(uint8_t id, uint16_t addr, const Bytes &data)
{
	Bytes params = { uint8_t(addr), uint8_t(addr >> 8) };
	params.insert(params.end(), data.begin(), data.end());
	return tcs::dxl2_instruction(id, tcs::kDxlWrite, params);
}

inline Bytes read_of(uint8_t id, uint16_t addr, uint16_t n)
{
	return tcs::dxl2_instruction(id, tcs::kDxlRead,
				     Bytes{ uint8_t(addr), uint8_t(addr >> 8), uint8_t(n), uint8_t(n >> 8) });
}

inline Bytes le(int64_t v, int bytes)
{
	Bytes out;
	for (int i = 0; i < bytes; i++)
		out.push_back(uint8_t(uint64_t(v) >> (8 * i)));
	return out;
}

// The joint angle whose Present Position is `counts` (at power-on, no
// offset): 2048 is 0 rad.
inline double angle_of(double counts)
{
	return (counts - 2048) * 2 * std::numbers::pi / 4096;
}

} // namespace dxl_checks
