// Generic frames of signals (a scenario's [[can.frame]]): fields of a
// given type, scale, offset and byte order at byte positions of the data.
// A field's raw value is round((value − offset) / scale) saturated to its
// type (NaN: 0); float32 holds (value − offset) / scale as an IEEE single
// (a finite value past its range saturated to ±FLT_MAX; NaN and infinities
// kept). Read back: raw · scale + offset.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "can_frame.h"
#include "error.h"

namespace tcs {

enum class CanType : uint8_t { int8, int16, int32, uint8, uint16, uint32, float32 };
enum class CanByteOrder : uint8_t { little, big };

struct CanField {
	std::string name;
	CanType type = CanType::uint8;
	double scale = 1, offset = 0;
	CanByteOrder order = CanByteOrder::little;
	int start = -1; // its first byte; -1: right after the field before it (the first: 0)
};

struct CanLayout {
	std::vector<CanField> fields; // every start resolved
	uint8_t end = 0;              // the bytes the fields need
	uint8_t len = 0;              // the frame's: end, for FD the FD length holding it
	bool fd = false;
};

size_t can_type_size(CanType type);

// The layout of the fields, in declaration order; refused, naming the
// field, when one overlaps another, ends past 8 bytes (64 for FD), starts
// before 0, or has a scale that is 0 or not finite or an offset not finite.
Result<CanLayout> can_layout(std::vector<CanField> fields, bool fd);
// values: one per field, in order. Sets the frame's len, fd and data (zeros
// where no field is); its id and other flags are the caller's.
void can_pack(const CanLayout &layout, const double *values, CanFrame &frame);
// The fields' values (values is resized to one per field). A frame shorter
// than the fields need is refused: false, *why (if why) says so, values
// left as they were.
bool can_unpack(const CanLayout &layout, const CanFrame &frame, std::vector<double> &values, std::string *why);

} // namespace tcs
