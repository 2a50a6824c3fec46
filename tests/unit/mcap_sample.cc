// The writer tests' sample messages and their files' folder (see
// mcap_sample.h).
#include "mcap_sample.h"

#include <sys/stat.h>
#include <unistd.h>

#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdio>
#include <cstdlib>

extern "C" {
#include <cmocka.h>
}

#include "result_checks.h"

namespace mcap_check {

namespace {

std::string g_dir;
bool g_keep = false;
std::vector<std::string> g_files;

} // namespace

const char kSliceSchema[] = R"({"type":"object","properties":{"controller":{"type":"string"},)"
			    R"("start_ns":{"type":"integer"},"end_ns":{"type":"integer"}}})";
const char kClockSchema[] = R"({"type":"object","properties":{"t_ns":{"type":"integer"}}})";

void Sample::setup(tcs::McapWriter &w)
{
	uint16_t slice = MUST(w.add_schema("tcs.Slice", kSliceSchema));
	uint16_t clock = MUST(w.add_schema("tcs.Clock", kClockSchema));
	ch[0] = MUST(w.add_channel("/clock", clock));
	ch[1] = MUST(w.add_channel("/tcs/slices/a", slice, { { "controller", "pendulum_pd" } }));
	ch[2] = MUST(w.add_channel("/tcs/slices/b", slice));
}

Msg Sample::next(int i)
{
	int k = i % 5 == 0 ? 0 : 1 + i % 2;
	uint64_t t = 1'000'000 + 1000 * uint64_t(i);
	std::string json = k == 0 ? "{\"t_ns\":" + std::to_string(t) + "}"
				  : "{\"controller\":\"c" + std::to_string(k) + std::string(i % 23, 'x') +
					    "\",\"start_ns\":" + std::to_string(t) + ",\"end_ns\":" + std::to_string(t + 500) +
					    "}";
	return Msg{ ch[k], seq[k]++, t, t + 7, json };
}

void Sample::write(tcs::McapWriter &w, int from, int to)
{
	for (int i = from; i < to; i++) {
		Msg m = next(i);
		CHECK_OK(w.write(m.channel, m.log, m.pub, m.data));
		expected.push_back(std::move(m));
	}
}

bool test_dir_open(const char *prefix)
{
	if (const char *keep = getenv("TCS_MCAP_TEST_DIR"); keep && *keep) {
		g_dir = keep;
		g_keep = true;
		mkdir(keep, 0777);
		return true;
	}
	std::string tmpl = std::string("/tmp/") + prefix + "-XXXXXX";
	if (!mkdtemp(tmpl.data())) {
		perror("mkdtemp");
		return false;
	}
	g_dir = tmpl;
	return true;
}

void test_dir_close()
{
	if (g_keep) {
		printf("# MCAP files kept in %s\n", g_dir.c_str());
		return;
	}
	for (const std::string &p : g_files)
		unlink(p.c_str());
	rmdir(g_dir.c_str());
}

std::string test_path(const std::string &name)
{
	std::string p = g_dir + "/" + name;
	g_files.push_back(p);
	return p;
}

std::string slurp(const std::string &path)
{
	std::string out;
	FILE *f = std::fopen(path.c_str(), "rb");
	assert_non_null(f);
	char buf[65536];
	size_t n;
	while ((n = std::fread(buf, 1, sizeof buf, f)) > 0)
		out.append(buf, n);
	std::fclose(f);
	return out;
}

void spit(const std::string &path, std::string_view bytes)
{
	FILE *f = std::fopen(path.c_str(), "wb");
	assert_non_null(f);
	assert_int_equal(std::fwrite(bytes.data(), 1, bytes.size(), f), bytes.size());
	assert_int_equal(std::fclose(f), 0);
}

} // namespace mcap_check
