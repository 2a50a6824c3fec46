// What a fuzz target gives standalone_driver.cc besides its
// LLVMFuzzerTestOneInput: a name, seed inputs, tokens worth splicing in and
// optionally a mutation that knows its input's structure. libFuzzer builds
// use LLVMFuzzerTestOneInput alone; the driver writes the seeds and tokens
// out for them (--write-seeds, --write-dict).
#pragma once

#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

namespace tcs_fuzz {

// Aborts, naming the line, when a promise of the code under test is broken.
inline void check(bool promise, int line = __builtin_LINE(), const char *file = __builtin_FILE())
{
	if (!promise) {
		fprintf(stderr, "%s:%d: broken promise\n", file, line);
		abort();
	}
}

// splitmix64: small, fast, and the same sequence everywhere for a seed.
class Rng {
public:
	explicit Rng(uint64_t seed) : s_(seed) {}
	uint64_t next()
	{
		uint64_t z = (s_ += 0x9E3779B97F4A7C15ull);
		z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
		z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
		return z ^ (z >> 31);
	}
	size_t below(size_t n) { return n ? size_t(next() % n) : 0; }

private:
	uint64_t s_;
};

// A little-endian field; the bytes past the end read as zeros.
inline uint64_t get_le(const std::string &s, size_t at, int bytes = 8)
{
	uint64_t v = 0;
	for (int i = 0; i < bytes && at + i < s.size(); i++)
		v |= uint64_t(uint8_t(s[at + i])) << (8 * i);
	return v;
}

// What write(path) writes to a file at path, which is a memfd's (a seed made
// in memory: no file left behind); empty if there is none.
inline std::string written_file(const std::function<void(const std::string &path)> &write)
{
	int fd = memfd_create("tcs_fuzz_seed", MFD_CLOEXEC);
	if (fd < 0)
		return {};
	write("/proc/self/fd/" + std::to_string(fd));
	std::string out;
	char buf[65536];
	ssize_t n;
	for (off_t at = 0; (n = pread(fd, buf, sizeof buf, at)) > 0; at += n)
		out.append(buf, size_t(n));
	close(fd);
	return out;
}

// Writes what fits of a little-endian field.
inline void put_le(std::string &s, size_t at, uint64_t v, int bytes)
{
	for (int i = 0; i < bytes && at + i < s.size(); i++)
		s[at + i] = char(v >> (8 * i));
}

// Values that make a length, a size or an index lie, for an input of size bytes.
inline uint64_t lying_value(Rng &rng, size_t size)
{
	const uint64_t values[] = { UINT64_MAX, uint64_t(1) << 63, uint64_t(1) << 40, uint64_t(1) << 32, UINT32_MAX,
				    0x7FFFFFFF, uint64_t(1) << 30, uint64_t(1) << 30 | 1, size, size + 1, 0 };
	return values[rng.below(sizeof values / sizeof values[0])];
}

} // namespace tcs_fuzz

// Each target file defines these four.
const char *tcs_fuzz_name();
// Inputs to start from: valid ones of every kind, and known edge cases.
std::vector<std::string> tcs_fuzz_seeds();
// Tokens the driver inserts or writes over the input (keywords, numbers,
// field values); also written as a libFuzzer dictionary.
std::vector<std::string> tcs_fuzz_tokens();
// A mutation that knows the input's structure; false when it has none
// for this input (the driver then mutates blindly).
bool tcs_fuzz_mutate(std::string &input, tcs_fuzz::Rng &rng);
