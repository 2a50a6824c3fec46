// The fuzz target for the device record formats (coordinator/device.h):
// what a controller writes to an actuator, taken apart by parse_records()
// in text or binary and for 1 to 16 values a record, all at once and in
// pieces as the socket delivers them; the preload's quick look
// (tcs/record_check.h), which must never vouch for what the parser
// refuses; and format_record(), which makes
// sensor records, given any values. The first byte of an input picks the
// format, the width and the pieces; the rest is what was written.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "device.h"
#include "fuzz_target.h"
#include "tcs/record_check.h"

namespace {

using Records = std::vector<std::vector<double>>;

// parse_records' limit on a text line still without its newline.
constexpr size_t kMaxLine = 4096;

using tcs_fuzz::check;

bool same_bits(const std::vector<double> &a, const std::vector<double> &b)
{
	return a.size() == b.size() && (a.empty() || memcmp(a.data(), b.data(), a.size() * sizeof a[0]) == 0);
}

bool same_records(const Records &a, const Records &b)
{
	if (a.size() != b.size())
		return false;
	for (size_t i = 0; i < a.size(); i++)
		if (!same_bits(a[i], b[i]))
			return false;
	return true;
}

// What parse_records promises of one call.
void check_call(int format, size_t width, bool ok, const std::string &left, const Records &records, size_t before,
		const std::string &why)
{
	for (size_t i = before; i < records.size(); i++) {
		check(records[i].size() == width);
		for (double v : records[i])
			check(std::isfinite(v));
	}
	if (!ok) {
		check(!why.empty());
		return;
	}
	if (format == TCS_FORMAT_BINARY)
		check(width == 0 || left.size() < 8 * width);
	else
		check(left.find('\n') == std::string::npos && left.size() <= kMaxLine);
}

// Parses as the coordinator does after each receive: records kept, going
// on past a malformed one (the write that carried it fails, later ones count).
Records parse_all(int format, size_t width, const std::string &bytes, const std::vector<size_t> &cuts,
		  size_t *malformed)
{
	Records records;
	std::string input;
	size_t from = 0;
	*malformed = 0;
	for (size_t k = 0; k <= cuts.size(); k++) {
		const size_t to = k < cuts.size() ? cuts[k] : bytes.size();
		input.append(bytes, from, to - from);
		from = to;
		for (;;) {
			const size_t before = records.size(), had = input.size();
			std::string why;
			const bool ok = tcs::parse_records(format, width, input, records, &why);
			check_call(format, width, ok, input, records, before, why);
			if (ok)
				break;
			(*malformed)++;
			check(input.size() < had); // the malformed record is gone
		}
	}
	return records;
}

// The record's values written by format_record, parsed back exactly.
void check_round_trip(int format, const std::vector<double> &values)
{
	const std::string rec = tcs::format_record(format, values);
	if (format == TCS_FORMAT_BINARY)
		check(rec.size() == 8 * values.size());
	else
		check(!rec.empty() && rec.back() == '\n' && rec.find('\n') == rec.size() - 1);
	bool finite = true;
	for (double v : values)
		finite = finite && std::isfinite(v);
	std::string input = rec;
	Records back;
	std::string why;
	const bool ok = tcs::parse_records(format, values.size(), input, back, &why);
	if (!finite) {
		// A sensor may carry a world gone wrong; an actuator refuses it.
		check(!ok);
		return;
	}
	check(ok && input.empty() && back.size() == (values.empty() ? 0u : 1u));
	if (!back.empty())
		check(same_bits(back[0], values));
}

bool has_long_line(const std::string &s)
{
	size_t start = 0;
	for (size_t nl; (nl = s.find('\n', start)) != std::string::npos; start = nl + 1)
		if (nl - start > kMaxLine)
			return true;
	return s.size() - start > kMaxLine;
}

std::string f64s(const std::vector<double> &values)
{
	return tcs::format_record(TCS_FORMAT_BINARY, values);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size == 0)
		return 0;
	const int format = data[0] & 1 ? TCS_FORMAT_BINARY : TCS_FORMAT_TEXT;
	const size_t width = (data[0] >> 1 & 15) + 1;
	const std::string bytes(reinterpret_cast<const char *>(data) + 1, size - 1);

	// Whole, then in pieces: one per byte, or at every k-th byte.
	std::vector<size_t> none, cuts;
	const size_t every = data[0] >> 5 ? size_t(data[0] >> 5) : 1;
	for (size_t at = every; at < bytes.size() && bytes.size() < 20000; at += every)
		cuts.push_back(at);
	size_t bad_whole, bad_cut;
	const Records whole = parse_all(format, width, bytes, none, &bad_whole);
	const Records cut = parse_all(format, width, bytes, cuts, &bad_cut);
	// Pieces change nothing, but where a text line grows past the limit
	// before its newline comes: that depends on how it arrives.
	if (format == TCS_FORMAT_BINARY || !has_long_line(bytes)) {
		check(same_records(whole, cut));
		check(bad_whole == bad_cut);
	}

	// What the preload sends on without a round trip (lockstep), the
	// parser takes whole: every record, nothing malformed, nothing left.
	const long vouched = tcs_records_check(bytes.data(), bytes.size(), (uint32_t)format, (uint32_t)width);
	if (vouched >= 0) {
		check(bad_whole == 0 && (long)whole.size() == vouched);
		std::string input = bytes;
		Records records;
		std::string why;
		check(tcs::parse_records(format, width, input, records, &why) && input.empty());
	}

	// Every record parsed is written again, in both formats, the same.
	for (const auto &values : whole) {
		check_round_trip(TCS_FORMAT_TEXT, values);
		check_round_trip(TCS_FORMAT_BINARY, values);
	}
	// Any values, as a sensor record: the input read as f64s.
	std::vector<double> values(bytes.size() / 8);
	if (!values.empty())
		memcpy(values.data(), bytes.data(), values.size() * 8);
	if (values.size() > 64)
		values.resize(64);
	check_round_trip(TCS_FORMAT_TEXT, values);
	check_round_trip(TCS_FORMAT_BINARY, values);
	return 0;
}

const char *tcs_fuzz_name()
{
	return "records_fuzz";
}

std::vector<std::string> tcs_fuzz_seeds()
{
	// The first byte: binary (1) or text (0), width - 1 in bits 1-4, the
	// size of the pieces in bits 5-7.
	auto head = [](int format, size_t width, size_t piece) {
		return std::string(1, char((format == TCS_FORMAT_BINARY) | (width - 1) << 1 | piece << 5));
	};
	const int T = TCS_FORMAT_TEXT, B = TCS_FORMAT_BINARY;
	return {
		head(T, 1, 0) + "0.75\n-1.5\n\n3e2\n",
		head(T, 2, 3) + "1 2\n3,4\n 5\t6\r\n7 8",
		head(T, 3, 1) + "1 2 3\n1 2\nx y z\n4 5 6\n",
		head(T, 1, 7) + "nan\ninf\n-inf\n1e999\n1e-999\n0x1p3\n-0\n",
		head(T, 7, 2) + "0.1 0.2 0.3 0.4 0.5 0.6 0.7\n",
		head(T, 16, 0) + "1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16\n",
		head(T, 1, 0) + std::string(5000, '1') + "\n2\n",
		head(T, 1, 0) + "9e299\n1e300\n00000000001e299\n.5\n5.\n+1\n",
		head(T, 2, 0) + ",,\n1.5-2\n1e 2\n",
		head(B, 1, 0) + f64s({ 0.75, -1.5, 1e-310 }),
		head(B, 2, 5) + f64s({ 1, 2, 3, 4, 5 }),
		head(B, 3, 0) + f64s({ 1, NAN, 3, 4, 5, 6 }),
		head(B, 1, 3) + f64s({ INFINITY, -0.0, 5e-324, 1.7976931348623157e308 }),
		head(B, 16, 1) + f64s(std::vector<double>(32, 0.5)),
	};
}

std::vector<std::string> tcs_fuzz_tokens()
{
	return { "\n", " ", ",", "\t", "\r", "-", "+", ".", "e", "e-", "E+308", "nan", "inf", "infinity", "0x",
		 "p-1074", "1e308", "1e-320", "-0", "4.9406564584124654e-324", "1.7976931348623157e308",
		 f64s({ NAN }), f64s({ INFINITY }), f64s({ -0.0 }) };
}

// A number, as the other format would not write it, somewhere in the text.
bool tcs_fuzz_mutate(std::string &s, tcs_fuzz::Rng &rng)
{
	if (s.empty() || s[0] & 1)
		return false;
	char buf[64];
	uint64_t bits = rng.next();
	double v;
	memcpy(&v, &bits, 8);
	snprintf(buf, sizeof buf, rng.below(2) ? "%.17g" : "%a", v);
	s.insert(1 + rng.below(s.size()), std::string(buf) + (rng.below(2) ? "\n" : " "));
	return true;
}
