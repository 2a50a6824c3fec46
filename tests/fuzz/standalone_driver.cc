// A main for the fuzz target where libFuzzer is not at hand (gcc builds):
// for --seconds it feeds LLVMFuzzerTestOneInput the seeds and random
// mutations of them, in an order fixed by a printed --seed. Without seed
// files it makes its own traces with McapWriter. Not coverage-guided, so
// its mutations aim at what the reader trusts least: lengths and sizes.
//
// It fails only when misused; a bug in the target crashes it (the build
// adds sanitizers), and the input that did is saved for a unit test.
#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "mcap_writer.h"

#if defined(__SANITIZE_ADDRESS__)
#define TCS_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define TCS_SANITIZED 1
#endif
#endif
#ifdef TCS_SANITIZED
#include <sanitizer/common_interface_defs.h>
#endif

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

namespace {

const char kUsage[] = "usage: trace_reader_fuzz [--seconds N] [--seed S] [--max-len BYTES] [SEED_FILE|DIR...]\n"
		      "       trace_reader_fuzz --write-seeds DIR\n";

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

// ---- Saving the input that crashed ----

// The input being run, and where to save it, ready before anything can go
// wrong: the handlers below only call write(2) and friends.
const uint8_t *g_input = nullptr;
size_t g_input_size = 0;
char g_crash_path[256];

void save_input()
{
	int fd = ::open(g_crash_path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
	if (fd < 0)
		return;
	for (size_t done = 0; done < g_input_size;) {
		ssize_t n = ::write(fd, g_input + done, g_input_size - done);
		if (n <= 0)
			break;
		done += size_t(n);
	}
	::close(fd);
	const char msg[] = "trace_reader_fuzz: the input that crashed is saved in ";
	(void)!::write(2, msg, sizeof msg - 1);
	(void)!::write(2, g_crash_path, strlen(g_crash_path));
	(void)!::write(2, "\n", 1);
}

void on_fatal_signal(int sig)
{
	save_input();
	signal(sig, SIG_DFL);
	raise(sig);
}

void catch_crashes()
{
	// With sanitizers, their handlers report memory errors and call back;
	// ours would hide their report. abort() and traps are ours anyway.
#ifdef TCS_SANITIZED
	__sanitizer_set_death_callback(save_input);
	const int sigs[] = { SIGABRT, SIGILL };
#else
	const int sigs[] = { SIGABRT, SIGILL, SIGSEGV, SIGBUS, SIGFPE };
#endif
	for (int sig : sigs)
		signal(sig, on_fatal_signal);
}

// ---- Seeds ----

bool read_file(const std::string &path, std::string &out)
{
	FILE *f = fopen(path.c_str(), "rbe");
	if (!f)
		return false;
	char buf[65536];
	size_t n;
	while ((n = fread(buf, 1, sizeof buf, f)) > 0)
		out.append(buf, n);
	bool ok = !ferror(f);
	fclose(f);
	return ok;
}

// Seed files, and the regular files in seed directories.
bool load_seeds(const std::vector<std::string> &paths, std::vector<std::string> &seeds)
{
	for (const std::string &p : paths) {
		struct stat st;
		if (stat(p.c_str(), &st) < 0) {
			fprintf(stderr, "trace_reader_fuzz: %s: %s\n", p.c_str(), strerror(errno));
			return false;
		}
		std::vector<std::string> files;
		if (S_ISDIR(st.st_mode)) {
			DIR *d = opendir(p.c_str());
			if (!d) {
				fprintf(stderr, "trace_reader_fuzz: %s: %s\n", p.c_str(), strerror(errno));
				return false;
			}
			while (struct dirent *e = readdir(d))
				if (e->d_name[0] != '.')
					files.push_back(p + "/" + e->d_name);
			closedir(d);
		} else {
			files.push_back(p);
		}
		for (const std::string &f : files) {
			std::string bytes;
			struct stat fst;
			if (stat(f.c_str(), &fst) == 0 && !S_ISREG(fst.st_mode))
				continue;
			if (!read_file(f, bytes)) {
				fprintf(stderr, "trace_reader_fuzz: %s: %s\n", f.c_str(), strerror(errno));
				return false;
			}
			seeds.push_back(std::move(bytes));
		}
	}
	return true;
}

// A little-endian field; the bytes past the end read as zeros.
uint64_t get_le(const std::string &s, size_t at, int bytes = 8)
{
	uint64_t v = 0;
	for (int i = 0; i < bytes && at + i < s.size(); i++)
		v |= uint64_t(uint8_t(s[at + i])) << (8 * i);
	return v;
}

void put_le(std::string &s, size_t at, uint64_t v, int bytes)
{
	for (int i = 0; i < bytes && at + i < s.size(); i++)
		s[at + i] = char(v >> (8 * i));
}

// The offsets of the complete top-level records of an MCAP file.
std::vector<size_t> records(const std::string &f)
{
	std::vector<size_t> out;
	for (size_t pos = 8; pos < f.size() && f.size() - pos >= 9;) {
		uint64_t len = get_le(f, pos + 1);
		if (len > f.size() - pos - 9)
			break;
		out.push_back(pos);
		pos += 9 + size_t(len);
	}
	return out;
}

// A trace as tcs writes them, in memory (a memfd stands in for the file).
std::string written_trace(tcs::McapCompression compression, int messages)
{
	int fd = memfd_create("trace_reader_fuzz", MFD_CLOEXEC);
	if (fd < 0)
		return {};
	std::string path = "/proc/self/fd/" + std::to_string(fd);
	{
		tcs::McapWriter w(tcs::McapWriterOptions{ .chunk_size = 300, .compression = compression });
		if (!w.open(path, "x-tcs", "fuzz").ok()) {
			::close(fd);
			return {};
		}
		auto schema = w.add_schema("tcs.Slice", R"({"type":"object"})");
		auto a = w.add_channel("/tcs/slices", schema.ok() ? *schema : 0, { { "controller", "pd" } });
		auto b = w.add_channel("/clock", 0);
		for (int i = 0; i < messages && a.ok() && b.ok(); i++) {
			std::string json = i % 3 ? "{\"t_ns\":" + std::to_string(1000 * i) + "}"
						 : "{\"name\":\"c\\u00e9\\ud83d\\ude00\\n\",\"v\":[1,-2.5e-3,9007199254740993,true,"
						   "null,{\"x\":[]}],\"i\":" +
							   std::to_string(i) + "}";
			(void)w.write(i % 3 ? *b : *a, uint64_t(i), uint64_t(i), json);
		}
		(void)w.close();
	}
	std::string out;
	char buf[65536];
	ssize_t n;
	for (off_t at = 0; (n = pread(fd, buf, sizeof buf, at)) > 0; at += n)
		out.append(buf, size_t(n));
	::close(fd);
	return out;
}

// The same trace with its chunks' CRCs zeroed ("not computed"), so that
// mutations of their records reach the record and JSON parsers; and with
// the records taken out of their chunks, as messages outside any chunk.
std::string without_crcs(std::string f)
{
	for (size_t at : records(f))
		if (f[at] == 0x06 && f.size() - at >= 9 + 28)
			put_le(f, at + 9 + 24, 0, 4);
	return f;
}

std::string unchunked(const std::string &f)
{
	std::string out = f.substr(0, 8);
	for (size_t at : records(f)) {
		const size_t len = size_t(get_le(f, at + 1));
		if (f[at] == 0x07) // Message Index: points into chunks no more
			continue;
		const size_t records_len_at = at + 9 + 28 + 4; // past an empty compression string
		if (f[at] == 0x06 && len >= 28 + 4 + 8 && get_le(f, at + 9 + 28, 4) == 0) // uncompressed
			out += f.substr(records_len_at + 8, size_t(get_le(f, records_len_at)));
		else
			out += f.substr(at, 9 + len);
	}
	return out + f.substr(f.size() - 8);
}

std::vector<std::string> own_seeds()
{
	std::string zstd = written_trace(tcs::McapCompression::zstd, 40);
	std::string none = written_trace(tcs::McapCompression::none, 40);
	return {
		zstd,
		none,
		without_crcs(none),
		unchunked(none),
		zstd.substr(0, zstd.size() / 2),
		written_trace(tcs::McapCompression::zstd, 0),
		R"({"a":[1,2.5e10,-0,"x\"\\\/\b\f\n\r\t\u0041\ud83d\ude00"],"b":{"c":null,"d":true,"e":false}})",
		"[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[1]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]",
		"-9223372036854775808 ",
		"\"\xc3\xa9\xe2\x82\xac\xf0\x9f\x98\x80\"",
	};
}

// ---- Mutations ----

// Values that make a length or size field lie.
uint64_t huge(Rng &rng, size_t size)
{
	const uint64_t values[] = { UINT64_MAX, uint64_t(1) << 63, uint64_t(1) << 40, uint64_t(1) << 32, UINT32_MAX,
				    0x7FFFFFFF, uint64_t(1) << 30, uint64_t(1) << 30 | 1, size, size + 1, 0 };
	return values[rng.below(sizeof values / sizeof values[0])];
}

void mutate_once(std::string &s, Rng &rng, const std::vector<std::string> &seeds)
{
	const size_t n = s.size();
	switch (rng.below(9)) {
	case 0: // flip a bit
		if (n)
			s[rng.below(n)] ^= char(1 << rng.below(8));
		break;
	case 1: { // an interesting byte
		const uint8_t bytes[] = { 0, 1, 0x7F, 0x80, 0xFF, '"', '\\', '[', '{', 0x06, 0x05 };
		if (n)
			s[rng.below(n)] = char(bytes[rng.below(sizeof bytes)]);
		break;
	}
	case 2: // cut short
		s.resize(rng.below(n + 1));
		break;
	case 3: { // insert random bytes
		std::string add(1 + rng.below(16), '\0');
		for (char &c : add)
			c = char(rng.next());
		s.insert(rng.below(n + 1), add);
		break;
	}
	case 4: { // duplicate a range
		size_t from = rng.below(n + 1), len = rng.below(std::min<size_t>(n - from, 512) + 1);
		s.insert(rng.below(n + 1), s.substr(from, len));
		break;
	}
	case 5: { // erase a range
		size_t from = rng.below(n + 1);
		s.erase(from, rng.below(std::min<size_t>(n - from, 64) + 1));
		break;
	}
	case 6: // a huge value anywhere
		if (n >= 8)
			put_le(s, rng.below(n - 7), huge(rng, n), rng.below(2) ? 8 : 4);
		break;
	case 7: { // a record's length, or a chunk's sizes, made to lie
		std::vector<size_t> recs = records(s);
		if (recs.empty())
			break;
		size_t at = recs[rng.below(recs.size())];
		const size_t fields[] = { 1, 9 + 16, 9 + 24, 9 + 28, 9 + 32 }; // len, usize, crc, compression, records len
		const size_t field = s[at] == 0x06 ? fields[rng.below(5)] : 1;
		const int bytes = field == 9 + 24 || field == 9 + 28 ? 4 : 8;
		const uint64_t v = rng.below(2) ? huge(rng, n) : get_le(s, at + field, bytes) + rng.below(17) - 8;
		put_le(s, at + field, v, bytes);
		break;
	}
	case 8: { // splice another seed's tail in
		const std::string &other = seeds[rng.below(seeds.size())];
		size_t at = rng.below(n + 1), from = rng.below(other.size() + 1);
		s = s.substr(0, at) + other.substr(from);
		break;
	}
	}
}

bool parse_u64(const char *text, uint64_t &out)
{
	char *end;
	errno = 0;
	out = strtoull(text, &end, 0);
	return errno == 0 && *text && !*end && text[0] != '-';
}

} // namespace

int main(int argc, char **argv)
{
	uint64_t seconds = 10, max_len = 1 << 20;
	uint64_t seed = uint64_t(std::chrono::system_clock::now().time_since_epoch().count()) ^ uint64_t(getpid());
	std::string write_dir;
	std::vector<std::string> paths;
	for (int i = 1; i < argc; i++) {
		std::string a = argv[i];
		if (a == "--help" || a == "-h") {
			fputs(kUsage, stdout);
			return 0;
		}
		bool has_value = i + 1 < argc;
		if (a == "--seconds" && has_value && parse_u64(argv[i + 1], seconds)) {
			i++;
		} else if (a == "--seed" && has_value && parse_u64(argv[i + 1], seed)) {
			i++;
		} else if (a == "--max-len" && has_value && parse_u64(argv[i + 1], max_len) && max_len > 0) {
			i++;
		} else if (a == "--write-seeds" && has_value) {
			write_dir = argv[++i];
		} else if (a.rfind("-", 0) == 0) {
			fprintf(stderr, "trace_reader_fuzz: bad option %s\n%s", a.c_str(), kUsage);
			return 2;
		} else {
			paths.push_back(a);
		}
	}

	std::vector<std::string> seeds;
	if (!load_seeds(paths, seeds))
		return 2;
	if (seeds.empty())
		seeds = own_seeds();
	if (!write_dir.empty()) {
		// A corpus to start libFuzzer from.
		for (size_t i = 0; i < seeds.size(); i++) {
			std::string p = write_dir + "/seed-" + std::to_string(i);
			FILE *f = fopen(p.c_str(), "wbe");
			if (!f || fwrite(seeds[i].data(), 1, seeds[i].size(), f) != seeds[i].size() || fclose(f) != 0) {
				fprintf(stderr, "trace_reader_fuzz: %s: %s\n", p.c_str(), strerror(errno));
				return 2;
			}
		}
		printf("trace_reader_fuzz: %zu seeds written to %s\n", seeds.size(), write_dir.c_str());
		return 0;
	}

	printf("trace_reader_fuzz: seed %" PRIu64 " (--seed %" PRIu64 " repeats this run), %zu seed inputs, %" PRIu64
	       " s\n",
	       seed, seed, seeds.size(), seconds);
	fflush(stdout);
	char cwd[128];
	snprintf(g_crash_path, sizeof g_crash_path, "%s/trace_reader_fuzz-crash-%" PRIu64,
		 getcwd(cwd, sizeof cwd) ? cwd : ".", seed);
	catch_crashes();

	Rng rng(seed);
	const auto start = std::chrono::steady_clock::now();
	const auto end = start + std::chrono::seconds(seconds);
	uint64_t runs = 0;
	std::string input;
	// An exact-size copy per input, so that reading past its end is a
	// sanitizer report rather than a read of spare capacity.
	auto run = [&](const std::string &s) {
		std::unique_ptr<uint8_t[]> copy(new uint8_t[s.size()]);
		memcpy(copy.get(), s.data(), s.size());
		g_input = copy.get();
		g_input_size = s.size();
		LLVMFuzzerTestOneInput(copy.get(), s.size());
		g_input = nullptr;
		runs++;
	};
	for (const std::string &s : seeds)
		run(s);
	while (std::chrono::steady_clock::now() < end) {
		input = seeds[rng.below(seeds.size())];
		for (size_t k = 1 + rng.below(4); k > 0; k--)
			mutate_once(input, rng, seeds);
		if (input.size() > max_len)
			input.resize(max_len);
		run(input);
	}
	const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
	printf("trace_reader_fuzz: %" PRIu64 " inputs in %.1f s (%.0f/s), seed %" PRIu64 "\n", runs, took,
	       took > 0 ? double(runs) / took : 0.0, seed);
	return 0;
}
