// The CAN fuzz target's bus half (can_fuzz.cc): a CanBus run through the
// submits and advances that bytes spell, its every delivery checked against
// a record of what was submitted.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

// Byte 0: bit rate (bits 0-1), a data bit rate (bit 2), the queue bound
// (bits 3-6). Then operations, by an op byte's low 2 bits: 0, 1 submit
// (source: bits 2-4; then id (2 bytes, or 4 when extended), flags and len,
// fill, ready); 2 advance (2 bytes: the step); 3 advance to next_end().
void can_bus_ops(const uint8_t *data, size_t size);
// An input for can_fuzz.cc (its first byte, odd, included).
std::string can_bus_seed();
