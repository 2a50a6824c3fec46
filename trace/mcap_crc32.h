// CRC-32 as MCAP (and zlib, PNG, Ethernet) define it, for the writer's and
// the reader's checks of chunks, the data section and the summary.
#pragma once

#include <cstddef>
#include <cstdint>

namespace tcs {

// Reflected polynomial 0xEDB88320, initial value and final xor 0xFFFFFFFF.
// Pass the previous result to continue over more bytes; start with 0.
uint32_t mcap_crc32(uint32_t crc, const void *data, size_t size);
// The same by tables alone, as on a CPU without carry-less multiplication
// (for the tests, which compare the two).
uint32_t mcap_crc32_by_tables(uint32_t crc, const void *data, size_t size);
// The CRC of A followed by B from A's CRC, B's and B's length, without
// reading either again (some 2,000 instructions whatever the length).
uint32_t mcap_crc32_combine(uint32_t crc_a, uint32_t crc_b, uint64_t size_b);

} // namespace tcs
