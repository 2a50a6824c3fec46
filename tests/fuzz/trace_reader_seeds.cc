// Seeds and mutations for the trace reader's fuzz target: traces written
// by McapWriter (zstd, uncompressed, with CRCs zeroed, unchunked, cut in
// half) and JSON texts; its mutation makes an MCAP record's length, or a
// chunk's sizes, lie — what the reader trusts least.
#include <sys/mman.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "fuzz_target.h"
#include "mcap_writer.h"

using tcs_fuzz::get_le;
using tcs_fuzz::put_le;

namespace {

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

} // namespace

const char *tcs_fuzz_name()
{
	return "trace_reader_fuzz";
}

std::vector<std::string> tcs_fuzz_seeds()
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

std::vector<std::string> tcs_fuzz_tokens()
{
	return { "\x89MCAP0\r\n", "\\u", "\\ud800", "\\udc00", "1e400", "-0", "true", "null", "\"\":" };
}

// A record's length, or a chunk's sizes, made to lie.
bool tcs_fuzz_mutate(std::string &s, tcs_fuzz::Rng &rng)
{
	std::vector<size_t> recs = records(s);
	if (recs.empty())
		return false;
	size_t at = recs[rng.below(recs.size())];
	const size_t fields[] = { 1, 9 + 16, 9 + 24, 9 + 28, 9 + 32 }; // len, usize, crc, compression, records len
	const size_t field = s[at] == 0x06 ? fields[rng.below(5)] : 1;
	const int bytes = field == 9 + 24 || field == 9 + 28 ? 4 : 8;
	const uint64_t v = rng.below(2) ? tcs_fuzz::lying_value(rng, s.size())
					: get_le(s, at + field, bytes) + rng.below(17) - 8;
	put_le(s, at + field, v, bytes);
	return true;
}
