// DxlControlTable: one servo's control table bytes, read and written as
// its READ and WRITE instructions do: Indirect Data through the Indirect
// Address that points it elsewhere, and a WRITE checked whole before any
// of it is applied.
//
// What a WRITE is refused for (the e-Manual's status errors):
//   Access Error (7): a byte past the table's end, in a gap between items,
//     in a read-only item, or in the EEPROM area while Torque Enable is 1
//     (or the packet came to the Secondary ID);
//   Data Length Error (5): an item written in part (2 of Goal Position's 4
//     bytes), as "Attempt to write Data that is shorter than the data
//     length of the corresponding Address" says;
//   Data Range / Data Limit Error (4 / 6): see dxl_check_value().
// The first byte refused, in address order, names the error; a refused
// WRITE changes nothing. A READ may span gaps (they read as 0, so that a
// whole area can be read at once); only a byte past the table is an
// Access Error.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "dynamixel_items.h"

namespace tcs {

enum class DxlReset {
	reboot,              // the RAM area to its initial values
	factory_all,         // everything (FACTORY_RESET 0xFF)
	factory_but_id,      // everything but ID (0x01)
	factory_but_id_baud, // everything but ID and Baud Rate (0x02)
};

class DxlControlTable {
public:
	DxlControlTable();

	// The item holding addr, as a number (0 for a gap); set() stores v in
	// it with no check (the servo's own registers).
	int64_t get(uint16_t addr) const;
	void set(uint16_t addr, int64_t v);

	void reset(DxlReset what);

	// READ: n bytes from addr into out; 0 or the status error, with why.
	uint8_t read(uint16_t addr, size_t n, std::vector<uint8_t> &out, std::string *why) const;

	// A WRITE checked: the table as it would be, and the items it writes
	// (by address, ascending).
	struct Staged {
		std::array<uint8_t, kDxlTableBytes> bytes;
		std::vector<uint16_t> items;
	};
	// 0 and `s` ready to commit, or the status error with why. ram_only:
	// the EEPROM area is locked (torque on is checked here too).
	uint8_t stage(uint16_t addr, const uint8_t *data, size_t n, bool ram_only, Staged &s, std::string *why) const;
	void commit(const Staged &s);

private:
	// Where a byte of the table really is: Indirect Data's, where its
	// Indirect Address points (unless at Indirect Data itself).
	uint16_t resolve(uint16_t addr) const;

	std::array<uint8_t, kDxlTableBytes> bytes_{};
};

} // namespace tcs
