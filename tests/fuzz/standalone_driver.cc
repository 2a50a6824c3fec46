// A main for any fuzz target where libFuzzer is not at hand (gcc builds):
// for --seconds it feeds LLVMFuzzerTestOneInput the seeds and random
// mutations of them, in an order fixed by a printed --seed (by default
// $TCS_FUZZ_SEED, else 1: the suite's runs repeat; explore with another,
// e.g. --seed $RANDOM). Without seed
// files it starts from the target's own (fuzz_target.h). Not
// coverage-guided, so besides blind mutations it splices in the target's
// tokens, makes numbers lie, and lets the target mutate its own structure.
//
// It fails only when misused; a bug in the target crashes it (the build
// adds sanitizers), and the input that did is saved for a unit test.
#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "fuzz_target.h"

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

namespace {

using tcs_fuzz::Rng;

void usage(FILE *to)
{
	const char *n = tcs_fuzz_name();
	fprintf(to,
		"usage: %s [--seconds N] [--seed S] [--max-len BYTES] [SEED_FILE|DIR...]\n"
		"       %s --write-seeds DIR [--write-dict FILE]\n",
		n, n);
}

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
	const char msg[] = ": the input that crashed is saved in ";
	(void)!::write(2, tcs_fuzz_name(), strlen(tcs_fuzz_name()));
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
			fprintf(stderr, "%s: %s: %s\n", tcs_fuzz_name(), p.c_str(), strerror(errno));
			return false;
		}
		std::vector<std::string> files;
		if (S_ISDIR(st.st_mode)) {
			DIR *d = opendir(p.c_str());
			if (!d) {
				fprintf(stderr, "%s: %s: %s\n", tcs_fuzz_name(), p.c_str(), strerror(errno));
				return false;
			}
			while (struct dirent *e = readdir(d))
				if (e->d_name[0] != '.')
					files.push_back(p + "/" + e->d_name);
			closedir(d);
			std::sort(files.begin(), files.end()); // the same run for the same --seed
		} else {
			files.push_back(p);
		}
		for (const std::string &f : files) {
			std::string bytes;
			struct stat fst;
			if (stat(f.c_str(), &fst) == 0 && !S_ISREG(fst.st_mode))
				continue;
			if (!read_file(f, bytes)) {
				fprintf(stderr, "%s: %s: %s\n", tcs_fuzz_name(), f.c_str(), strerror(errno));
				return false;
			}
			seeds.push_back(std::move(bytes));
		}
	}
	return true;
}

bool write_file(const std::string &path, const std::string &bytes)
{
	FILE *f = fopen(path.c_str(), "wbe");
	bool ok = f && fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
	if (f && fclose(f) != 0)
		ok = false;
	if (!ok)
		fprintf(stderr, "%s: %s: %s\n", tcs_fuzz_name(), path.c_str(), strerror(errno));
	return ok;
}

// The tokens as a libFuzzer dictionary: one quoted string a line.
std::string dictionary(const std::vector<std::string> &tokens)
{
	std::string out;
	for (const std::string &t : tokens) {
		out += '"';
		for (unsigned char c : t) {
			char hex[8];
			if (c < 0x20 || c >= 0x7F || c == '"' || c == '\\') {
				snprintf(hex, sizeof hex, "\\x%02X", c);
				out += hex;
			} else {
				out += char(c);
			}
		}
		out += "\"\n";
	}
	return out;
}

// ---- Mutations ----

void mutate_once(std::string &s, Rng &rng, const std::vector<std::string> &seeds,
		 const std::vector<std::string> &tokens)
{
	const size_t n = s.size();
	switch (rng.below(11)) {
	case 0: // flip a bit
		if (n)
			s[rng.below(n)] ^= char(1 << rng.below(8));
		break;
	case 1: { // an interesting byte
		const uint8_t bytes[] = { 0, 1, 0x7F, 0x80, 0xFF, '"', '\\', '[', '{', '\n', ' ', 0x06, 0x05 };
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
	case 6: // a lying value anywhere
		if (n >= 8)
			tcs_fuzz::put_le(s, rng.below(n - 7), tcs_fuzz::lying_value(rng, n), rng.below(2) ? 8 : 4);
		break;
	case 7: // the target's own idea
		if (!tcs_fuzz_mutate(s, rng) && n)
			s[rng.below(n)] ^= char(1 << rng.below(8));
		break;
	case 8: { // splice another seed's tail in
		const std::string &other = seeds[rng.below(seeds.size())];
		size_t at = rng.below(n + 1), from = rng.below(other.size() + 1);
		s = s.substr(0, at) + other.substr(from);
		break;
	}
	case 9: // insert a token
		if (!tokens.empty())
			s.insert(rng.below(n + 1), tokens[rng.below(tokens.size())]);
		break;
	case 10: // a token over what was there
		if (!tokens.empty()) {
			const std::string &t = tokens[rng.below(tokens.size())];
			s.replace(rng.below(n + 1), t.size(), t);
		}
		break;
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
	const char *name = tcs_fuzz_name();
	uint64_t seconds = 10, max_len = 1 << 20;
	uint64_t seed = 1;
	if (const char *env = getenv("TCS_FUZZ_SEED"); env && !parse_u64(env, seed)) {
		fprintf(stderr, "%s: TCS_FUZZ_SEED=%s is not a number\n", name, env);
		return 2;
	}
	std::string write_dir, dict_path;
	std::vector<std::string> paths;
	for (int i = 1; i < argc; i++) {
		std::string a = argv[i];
		if (a == "--help" || a == "-h") {
			usage(stdout);
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
		} else if (a == "--write-dict" && has_value) {
			dict_path = argv[++i];
		} else if (a.rfind("-", 0) == 0) {
			fprintf(stderr, "%s: bad option %s\n", name, a.c_str());
			usage(stderr);
			return 2;
		} else {
			paths.push_back(a);
		}
	}

	std::vector<std::string> seeds;
	if (!load_seeds(paths, seeds))
		return 2;
	if (seeds.empty())
		seeds = tcs_fuzz_seeds();
	const std::vector<std::string> tokens = tcs_fuzz_tokens();
	if (!write_dir.empty() || !dict_path.empty()) {
		// A corpus and a dictionary to start libFuzzer from.
		for (size_t i = 0; i < seeds.size() && !write_dir.empty(); i++)
			if (!write_file(write_dir + "/seed-" + std::to_string(i), seeds[i]))
				return 2;
		if (!dict_path.empty() && !write_file(dict_path, dictionary(tokens)))
			return 2;
		if (!write_dir.empty())
			printf("%s: %zu seeds written to %s\n", name, seeds.size(), write_dir.c_str());
		if (!dict_path.empty())
			printf("%s: %zu tokens written to %s\n", name, tokens.size(), dict_path.c_str());
		return 0;
	}

	printf("%s: seed %" PRIu64 " (--seed %" PRIu64 " repeats this run), %zu seed inputs, %" PRIu64 " s\n", name,
	       seed, seed, seeds.size(), seconds);
	fflush(stdout);
	char cwd[128];
	snprintf(g_crash_path, sizeof g_crash_path, "%s/%s-crash-%" PRIu64, getcwd(cwd, sizeof cwd) ? cwd : ".", name,
		 seed);
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
	if (seeds.empty())
		seeds.push_back(""); // mutations start from nothing
	while (std::chrono::steady_clock::now() < end) {
		input = seeds[rng.below(seeds.size())];
		for (size_t k = 1 + rng.below(4); k > 0; k--)
			mutate_once(input, rng, seeds, tokens);
		if (input.size() > max_len)
			input.resize(max_len);
		run(input);
	}
	const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
	printf("%s: %" PRIu64 " inputs in %.1f s (%.0f/s), seed %" PRIu64 "\n", name, runs, took,
	       took > 0 ? double(runs) / took : 0.0, seed);
	return 0;
}
