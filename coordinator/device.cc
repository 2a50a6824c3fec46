// Device record formats: text lines of numbers, or little-endian f64s.
#include "device.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace tcs {

std::string format_record(int format, const std::vector<double> &values)
{
	std::string out;
	if (format == TCS_FORMAT_BINARY) {
		for (double v : values) {
			unsigned char b[8];
			uint64_t bits;
			std::memcpy(&bits, &v, 8);
			for (int i = 0; i < 8; i++)
				b[i] = (unsigned char)(bits >> (8 * i));
			out.append(reinterpret_cast<const char *>(b), 8);
		}
		return out;
	}
	char buf[32];
	for (size_t i = 0; i < values.size(); i++) {
		snprintf(buf, sizeof buf, "%s%.17g", i ? " " : "", values[i]);
		out += buf;
	}
	out += '\n';
	return out;
}

namespace {

bool parse_text_line(const std::string &line, size_t width, std::vector<double> &values, std::string *why)
{
	const char *p = line.c_str();
	values.clear();
	for (;;) {
		while (*p == ' ' || *p == '\t' || *p == '\r' || *p == ',')
			p++;
		if (*p == '\0' && p != line.c_str() + line.size()) {
			// strtod would stop there and the rest be lost unseen.
			*why = "a line holds a NUL byte";
			return false;
		}
		if (*p == '\0')
			break;
		char *end;
		double v = strtod(p, &end);
		if (end == p || !std::isfinite(v)) {
			*why = "'" + line + "' is not " + std::to_string(width) + " number" + (width == 1 ? "" : "s");
			return false;
		}
		values.push_back(v);
		p = end;
	}
	if (values.size() != width) {
		*why = "'" + line + "' has " + std::to_string(values.size()) + " number" +
		       (values.size() == 1 ? "" : "s") + ", expected " + std::to_string(width);
		return false;
	}
	return true;
}

} // namespace

bool parse_records(int format, size_t width, std::string &input, std::vector<std::vector<double>> &records,
		   std::string *why)
{
	if (format == TCS_FORMAT_BINARY) {
		size_t size = 8 * width;
		while (input.size() >= size && size > 0) {
			std::vector<double> values(width);
			for (size_t i = 0; i < width; i++) {
				uint64_t bits = 0;
				for (int b = 0; b < 8; b++)
					bits |= (uint64_t)(unsigned char)input[8 * i + b] << (8 * b);
				std::memcpy(&values[i], &bits, 8);
			}
			input.erase(0, size);
			for (double v : values)
				if (!std::isfinite(v)) {
					*why = "a record holds a value that is not finite";
					return false;
				}
			records.push_back(std::move(values));
		}
		return true;
	}
	size_t nl;
	while ((nl = input.find('\n')) != std::string::npos) {
		std::string line = input.substr(0, nl);
		input.erase(0, nl + 1);
		if (line.find_first_not_of(" \t\r") == std::string::npos)
			continue; // blank lines carry nothing
		std::vector<double> values;
		if (!parse_text_line(line, width, values, why))
			return false;
		records.push_back(std::move(values));
	}
	if (input.size() > 4096) { // no newline in sight: not a text record
		*why = "a line longer than 4096 bytes";
		input.clear();
		return false;
	}
	return true;
}

} // namespace tcs
