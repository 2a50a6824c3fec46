// What the CAN unit tests share: a classic frame from its id and bytes.
#pragma once

#include <cstdint>
#include <initializer_list>

#include "can_frame.h"

inline tcs::CanFrame can_test_frame(uint32_t id, std::initializer_list<uint8_t> data, bool extended = false)
{
	tcs::CanFrame f;
	f.id = id;
	f.extended = extended;
	f.len = uint8_t(data.size());
	size_t i = 0;
	for (uint8_t b : data)
		f.data[i++] = b;
	return f;
}
