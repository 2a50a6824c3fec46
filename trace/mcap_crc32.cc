// MCAP's CRC-32, eight bytes at a time ("slicing-by-8"): the writer runs it
// over every byte it writes, so it is worth the tables.
#include "mcap_crc32.h"

namespace tcs {

namespace {

struct Crc32Tables {
	uint32_t t[8][256];
};

constexpr Crc32Tables make_crc32_tables()
{
	Crc32Tables tables{};
	for (uint32_t i = 0; i < 256; i++) {
		uint32_t c = i;
		for (int bit = 0; bit < 8; bit++)
			c = (c & 1) ? (c >> 1) ^ 0xEDB88320u : c >> 1;
		tables.t[0][i] = c;
	}
	// t[k][i]: the CRC of byte i followed by k zero bytes.
	for (int k = 1; k < 8; k++)
		for (int i = 0; i < 256; i++) {
			uint32_t prev = tables.t[k - 1][i];
			tables.t[k][i] = (prev >> 8) ^ tables.t[0][prev & 0xFF];
		}
	return tables;
}

constexpr Crc32Tables kCrc32 = make_crc32_tables();

inline uint32_t load_le32(const uint8_t *p)
{
	return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

} // namespace

uint32_t mcap_crc32(uint32_t crc, const void *data, size_t size)
{
	const uint8_t *p = static_cast<const uint8_t *>(data);
	const auto &t = kCrc32.t;
	uint32_t c = ~crc;
	for (; size >= 8; p += 8, size -= 8) {
		uint32_t lo = load_le32(p) ^ c;
		uint32_t hi = load_le32(p + 4);
		c = t[7][lo & 0xFF] ^ t[6][(lo >> 8) & 0xFF] ^ t[5][(lo >> 16) & 0xFF] ^ t[4][lo >> 24] ^
		    t[3][hi & 0xFF] ^ t[2][(hi >> 8) & 0xFF] ^ t[1][(hi >> 16) & 0xFF] ^ t[0][hi >> 24];
	}
	for (; size > 0; p++, size--)
		c = t[0][(c ^ *p) & 0xFF] ^ (c >> 8);
	return ~c;
}

} // namespace tcs
