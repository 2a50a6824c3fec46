// DxlControlTable: the bytes, indirection, and checking a WRITE (see
// dynamixel_control_table.h).
#include "dynamixel_control_table.h"
#include "dynamixel2_packet.h"

#include <algorithm>

namespace tcs {

namespace {

void store(uint8_t *bytes, const DxlItem &it, int64_t v)
{
	for (int i = 0; i < it.size; i++)
		bytes[it.addr + i] = uint8_t(uint64_t(v) >> (8 * i));
}

std::string where(uint16_t addr)
{
	return "address " + std::to_string(addr);
}

uint8_t refuse(uint8_t error, std::string *why, const std::string &what)
{
	if (why)
		*why = what;
	return error;
}

} // namespace

DxlControlTable::DxlControlTable()
{
	reset(DxlReset::factory_all);
}

int64_t DxlControlTable::get(uint16_t addr) const
{
	const std::optional<DxlItem> it = dxl_item(addr);
	return it ? dxl_value(bytes_.data(), *it) : 0;
}

void DxlControlTable::set(uint16_t addr, int64_t v)
{
	if (const std::optional<DxlItem> it = dxl_item(addr))
		store(bytes_.data(), *it, v);
}

void DxlControlTable::reset(DxlReset what)
{
	const int64_t id = get(kDxlId), baud = get(kDxlBaudRate);
	for (uint16_t a = what == DxlReset::reboot ? kDxlRamStart : 0; a < kDxlTableBytes;) {
		const std::optional<DxlItem> it = dxl_item(a);
		if (!it) {
			bytes_[a++] = 0;
			continue;
		}
		store(bytes_.data(), *it, it->initial);
		a = uint16_t(it->addr + it->size);
	}
	if (what == DxlReset::factory_but_id || what == DxlReset::factory_but_id_baud)
		set(kDxlId, id);
	if (what == DxlReset::factory_but_id_baud)
		set(kDxlBaudRate, baud);
}

uint16_t DxlControlTable::resolve(uint16_t addr) const
{
	const std::optional<uint16_t> pointer = dxl_indirect_address_of(addr);
	if (!pointer)
		return addr;
	const int64_t to = get(*pointer);
	if (to < 0 || to >= kDxlTableBytes || dxl_indirect_address_of(uint16_t(to)))
		return addr;
	return uint16_t(to);
}

uint8_t DxlControlTable::read(uint16_t addr, size_t n, std::vector<uint8_t> &out, std::string *why) const
{
	if (size_t(addr) + n > kDxlTableBytes)
		return refuse(kDxlAccessError, why,
			      "READ of " + std::to_string(n) + " bytes at " + std::to_string(addr) +
				      " runs past the control table (" + std::to_string(kDxlTableBytes) + " bytes)");
	for (size_t i = 0; i < n; i++) {
		const uint16_t at = resolve(uint16_t(addr + i));
		out.push_back(dxl_item(at) ? bytes_[at] : 0);
	}
	return 0;
}

uint8_t DxlControlTable::stage(uint16_t addr, const uint8_t *data, size_t n, bool ram_only, Staged &s,
			       std::string *why) const
{
	if (n == 0)
		return refuse(kDxlDataLengthError, why, "WRITE with no data");
	if (size_t(addr) + n > kDxlTableBytes)
		return refuse(kDxlAccessError, why,
			      "WRITE of " + std::to_string(n) + " bytes at " + std::to_string(addr) +
				      " runs past the control table (" + std::to_string(kDxlTableBytes) + " bytes)");
	const bool locked = ram_only || get(kDxlTorqueEnable) == 1;
	s.bytes = bytes_;
	s.items.clear();
	// Which bytes of each item written (bit i: byte i), to find items
	// written in part.
	std::vector<std::pair<DxlItem, unsigned>> touched;
	for (size_t i = 0; i < n; i++) {
		const uint16_t at = resolve(uint16_t(addr + i));
		const std::optional<DxlItem> it = dxl_item(at);
		if (!it)
			return refuse(kDxlAccessError, why, "WRITE to " + where(at) + ", which holds no item");
		if (!it->writable)
			return refuse(kDxlAccessError, why,
				      "WRITE to " + std::string(it->name) + " (" + std::to_string(it->addr) +
					      "), which is read-only");
		if (it->addr < kDxlRamStart && locked)
			return refuse(kDxlAccessError, why,
				      "WRITE to " + std::string(it->name) + " (" + std::to_string(it->addr) +
					      ") in the EEPROM area, locked " +
					      (ram_only ? "to the Secondary ID" : "while Torque Enable is 1"));
		s.bytes[at] = data[i];
		size_t k = 0;
		while (k < touched.size() && touched[k].first.addr != it->addr)
			k++;
		if (k == touched.size())
			touched.push_back({ *it, 0u });
		touched[k].second |= 1u << (at - it->addr);
	}
	for (const auto &[it, mask] : touched)
		if (mask != (1u << it.size) - 1)
			return refuse(kDxlDataLengthError, why,
				      "WRITE of part of " + std::string(it.name) + " (" + std::to_string(it.addr) +
					      ", " + std::to_string(it.size) + " bytes)");
	for (const auto &[it, mask] : touched)
		if (const uint8_t e = dxl_check_value(it, s.bytes.data(), why))
			return e;
	for (const auto &[it, mask] : touched)
		s.items.push_back(it.addr);
	std::sort(s.items.begin(), s.items.end());
	return 0;
}

void DxlControlTable::commit(const Staged &s)
{
	bytes_ = s.bytes;
}

} // namespace tcs
