// MCAP's CRC-32. The writer runs it over every byte it writes, twice (a
// chunk's CRC, and the data section's), on the coordinator's thread: where
// the CPU multiplies carry-less (x86-64's PCLMULQDQ), 64 bytes are folded at
// a time, some 0.3 instructions a byte; elsewhere, and for what is left of
// the folding, eight bytes at a time by tables ("slicing-by-8"), some 2.5.
#include "mcap_crc32.h"

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace tcs {

namespace {

// The polynomial, not reflected: x^32 + x^26 + ... + 1.
constexpr uint64_t kPoly = 0x104C11DB7ull;

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

// The CRC's register c (not inverted) carried over size bytes.
uint32_t crc_by_tables(uint32_t c, const uint8_t *p, size_t size)
{
	const auto &t = kCrc32.t;
	for (; size >= 8; p += 8, size -= 8) {
		uint32_t lo = load_le32(p) ^ c;
		uint32_t hi = load_le32(p + 4);
		c = t[7][lo & 0xFF] ^ t[6][(lo >> 8) & 0xFF] ^ t[5][(lo >> 16) & 0xFF] ^ t[4][lo >> 24] ^
		    t[3][hi & 0xFF] ^ t[2][(hi >> 8) & 0xFF] ^ t[1][(hi >> 16) & 0xFF] ^ t[0][hi >> 24];
	}
	for (; size > 0; p++, size--)
		c = t[0][(c ^ *p) & 0xFF] ^ (c >> 8);
	return c;
}

#if defined(__x86_64__)

// Folding (the register is the message's bits, first bit the highest power
// of x, 16 bytes loaded little-endian: bit n of the 128 stands for
// x^(127-n)). A block X followed by n more bits of message is worth
// X * x^n mod P: its first 64 bits (the low lane) times x^(n+64) and its
// last 64 times x^n, each reduced to 32 bits, can be xored into the block
// n bits further on. A constant is x^e mod P bit-reflected and shifted left
// by one (33 bits), which carries the product's own one-bit shift:
// multiplying the low lane by x^(n+32) mod P and the high one by
// x^(n-32) mod P gives them as bits of the block n further on.
constexpr uint64_t x_pow_mod(int e)
{
	uint64_t r = 1;
	for (int i = 0; i < e; i++) {
		r <<= 1;
		if (r & (1ull << 32))
			r ^= kPoly;
	}
	return r;
}

constexpr uint64_t fold_constant(int e)
{
	uint64_t r = x_pow_mod(e), reflected = 0;
	for (int i = 0; i < 32; i++)
		if (r & (1ull << i))
			reflected |= 1ull << (31 - i);
	return reflected << 1;
}

// By one block (128 bits) and by four (512).
constexpr uint64_t kFold1Lo = fold_constant(128 + 32), kFold1Hi = fold_constant(128 - 32);
constexpr uint64_t kFold4Lo = fold_constant(512 + 32), kFold4Hi = fold_constant(512 - 32);

__attribute__((target("pclmul"))) inline __m128i fold(__m128i x, __m128i k, __m128i next)
{
	__m128i lo = _mm_clmulepi64_si128(x, k, 0x00); // x's low lane, k's low
	__m128i hi = _mm_clmulepi64_si128(x, k, 0x11); // x's high lane, k's high
	return _mm_xor_si128(_mm_xor_si128(lo, hi), next);
}

// At least 64 bytes: folded to one block, whose CRC is then the tables'
// (its CRC and the message's are the same), and the rest by tables too.
__attribute__((target("pclmul"))) uint32_t crc_by_folding(uint32_t c, const uint8_t *p, size_t size)
{
	auto load = [](const uint8_t *q) { return _mm_loadu_si128(reinterpret_cast<const __m128i *>(q)); };
	const __m128i k4 = _mm_set_epi64x((long long)kFold4Hi, (long long)kFold4Lo);
	const __m128i k1 = _mm_set_epi64x((long long)kFold1Hi, (long long)kFold1Lo);
	// The register so far goes into the message's first 32 bits.
	__m128i x0 = _mm_xor_si128(load(p), _mm_cvtsi32_si128((int)c));
	__m128i x1 = load(p + 16), x2 = load(p + 32), x3 = load(p + 48);
	p += 64, size -= 64;
	for (; size >= 64; p += 64, size -= 64) {
		x0 = fold(x0, k4, load(p));
		x1 = fold(x1, k4, load(p + 16));
		x2 = fold(x2, k4, load(p + 32));
		x3 = fold(x3, k4, load(p + 48));
	}
	__m128i x = fold(fold(fold(x0, k1, x1), k1, x2), k1, x3);
	for (; size >= 16; p += 16, size -= 16)
		x = fold(x, k1, load(p));
	alignas(16) uint8_t block[16];
	_mm_store_si128(reinterpret_cast<__m128i *>(block), x);
	return crc_by_tables(crc_by_tables(0, block, 16), p, size);
}

// (In a static initialiser: the CPU's features are not known to the
// builtin before __builtin_cpu_init.)
const bool kHaveClmul = [] {
	__builtin_cpu_init();
	return __builtin_cpu_supports("pclmul") != 0;
}();

#endif

} // namespace

uint32_t mcap_crc32(uint32_t crc, const void *data, size_t size)
{
	const uint8_t *p = static_cast<const uint8_t *>(data);
#if defined(__x86_64__)
	if (size >= 64 && kHaveClmul)
		return ~crc_by_folding(~crc, p, size);
#endif
	return ~crc_by_tables(~crc, p, size);
}

uint32_t mcap_crc32_by_tables(uint32_t crc, const void *data, size_t size)
{
	return ~crc_by_tables(~crc, static_cast<const uint8_t *>(data), size);
}

namespace {

// Polynomials mod P as the reflected register holds them: bit 31 is x^0,
// bit 0 is x^31. a * b mod P, b taken times x once for each bit of a.
uint32_t multiply_mod(uint32_t a, uint32_t b)
{
	uint32_t product = 0;
	for (uint32_t bit = 1u << 31; bit != 0; bit >>= 1) {
		if (a & bit)
			product ^= b;
		b = (b & 1) ? (b >> 1) ^ 0xEDB88320u : b >> 1;
	}
	return product;
}

// x^(8 n) mod P, by squaring.
uint32_t x_pow_8n(uint64_t n)
{
	uint32_t result = 1u << 31, power = 1u << 23; // x^0, x^8
	for (; n != 0; n >>= 1) {
		if (n & 1)
			result = multiply_mod(result, power);
		power = multiply_mod(power, power);
	}
	return result;
}

} // namespace

// The register after A, carried over size_b zero bytes, is A's share of
// the CRC of A and B; the initial and final inversions cancel out between
// the two CRCs, so B's CRC is the rest.
uint32_t mcap_crc32_combine(uint32_t crc_a, uint32_t crc_b, uint64_t size_b)
{
	return multiply_mod(x_pow_8n(size_b), crc_a) ^ crc_b;
}

} // namespace tcs
