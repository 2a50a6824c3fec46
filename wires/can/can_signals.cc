// Frames of signals: layouts checked, values packed and unpacked (see can_signals.h).
#include "can_signals.h"

#include <cfloat>
#include <cmath>
#include <cstring>

namespace tcs {

namespace {

struct IntRange {
	double min, max;
};

IntRange int_range(CanType type)
{
	switch (type) {
	case CanType::int8:
		return { -128, 127 };
	case CanType::int16:
		return { -32768, 32767 };
	case CanType::int32:
		return { -2147483648.0, 2147483647.0 };
	case CanType::uint8:
		return { 0, 255 };
	case CanType::uint16:
		return { 0, 65535 };
	default:
		return { 0, 4294967295.0 };
	}
}

std::string bytes_of(const CanField &f)
{
	const size_t last = size_t(f.start) + can_type_size(f.type) - 1;
	return "field '" + f.name + "' (byte" +
	       (last == size_t(f.start) ? " " + std::to_string(f.start)
					: "s " + std::to_string(f.start) + ".." + std::to_string(last)) +
	       ")";
}

// The field's raw bits for value, in its low size bytes.
uint32_t raw_of(const CanField &f, double value)
{
	const double v = (value - f.offset) / f.scale;
	if (f.type == CanType::float32) {
		const double max = FLT_MAX;
		const float x = std::isfinite(v) ? float(std::fmin(std::fmax(v, -max), max)) : float(v);
		uint32_t bits;
		memcpy(&bits, &x, 4);
		return bits;
	}
	if (std::isnan(v))
		return 0;
	const IntRange r = int_range(f.type);
	const double q = std::fmin(std::fmax(std::round(v), r.min), r.max);
	return r.min < 0 ? uint32_t(int64_t(q)) : uint32_t(q);
}

double value_of(const CanField &f, uint32_t raw)
{
	double v;
	switch (f.type) {
	case CanType::int8:
		v = int8_t(raw);
		break;
	case CanType::int16:
		v = int16_t(raw);
		break;
	case CanType::int32:
		v = int32_t(raw);
		break;
	case CanType::float32: {
		float x;
		memcpy(&x, &raw, 4);
		v = x;
		break;
	}
	default:
		v = raw;
	}
	return v * f.scale + f.offset;
}

} // namespace

size_t can_type_size(CanType type)
{
	switch (type) {
	case CanType::int8:
	case CanType::uint8:
		return 1;
	case CanType::int16:
	case CanType::uint16:
		return 2;
	default:
		return 4;
	}
}

Result<CanLayout> can_layout(std::vector<CanField> fields, bool fd)
{
	const int room = fd ? 64 : 8;
	int owner[64]; // by byte: the field there, or -1
	for (int &o : owner)
		o = -1;
	int next = 0;
	CanLayout layout;
	layout.fd = fd;
	for (size_t i = 0; i < fields.size(); i++) {
		CanField &f = fields[i];
		if (f.scale == 0 || !std::isfinite(f.scale) || !std::isfinite(f.offset))
			return Error{ "field '" + f.name + "': scale must be finite and not 0, offset finite" };
		if (f.start < -1)
			return Error{ "field '" + f.name + "': start byte " + std::to_string(f.start) +
				      " is before 0" };
		if (f.start < 0)
			f.start = next;
		const int size = int(can_type_size(f.type));
		if (f.start > room - size)
			return Error{ bytes_of(f) + " ends past the frame's " + std::to_string(room) + " bytes" };
		for (int b = f.start; b < f.start + size; b++) {
			if (owner[b] >= 0)
				return Error{ bytes_of(f) + " overlaps " + bytes_of(fields[size_t(owner[b])]) };
			owner[b] = int(i);
		}
		next = f.start + size;
		if (next > layout.end)
			layout.end = uint8_t(next);
	}
	layout.len = fd ? can_fd_len(layout.end) : layout.end;
	layout.fields = std::move(fields);
	return layout;
}

void can_pack(const CanLayout &layout, const double *values, CanFrame &frame)
{
	frame.fd = layout.fd;
	frame.len = layout.len;
	memset(frame.data, 0, sizeof frame.data);
	for (size_t i = 0; i < layout.fields.size(); i++) {
		const CanField &f = layout.fields[i];
		const uint32_t raw = raw_of(f, values[i]);
		const size_t size = can_type_size(f.type);
		for (size_t k = 0; k < size; k++) {
			const size_t at = f.order == CanByteOrder::little ? k : size - 1 - k;
			frame.data[size_t(f.start) + at] = uint8_t(raw >> (8 * k));
		}
	}
}

bool can_unpack(const CanLayout &layout, const CanFrame &frame, std::vector<double> &values, std::string *why)
{
	if (frame.len < layout.end) {
		if (why)
			*why = "a frame of " + std::to_string(frame.len) + " bytes: its signals need " +
			       std::to_string(layout.end);
		return false;
	}
	values.resize(layout.fields.size());
	for (size_t i = 0; i < layout.fields.size(); i++) {
		const CanField &f = layout.fields[i];
		const size_t size = can_type_size(f.type);
		uint32_t raw = 0;
		for (size_t k = 0; k < size; k++) {
			const size_t at = f.order == CanByteOrder::little ? k : size - 1 - k;
			raw |= uint32_t(frame.data[size_t(f.start) + at]) << (8 * k);
		}
		values[i] = value_of(f, raw);
	}
	return true;
}

} // namespace tcs
