// A test program's folder of files (see test_files.h).
#include "test_files.h"

#include <sys/stat.h>
#include <unistd.h>

#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <vector>

extern "C" {
#include <cmocka.h>
}

namespace test_files {

namespace {

std::string g_dir;
bool g_keep = false;
std::vector<std::string> g_files;

} // namespace

bool test_dir_open(const char *prefix, const char *keep_env)
{
	if (const char *keep = keep_env ? getenv(keep_env) : nullptr; keep && *keep) {
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
		printf("# files kept in %s\n", g_dir.c_str());
		return;
	}
	for (const std::string &p : g_files)
		unlink(p.c_str());
	rmdir(g_dir.c_str());
}

const std::string &test_dir()
{
	return g_dir;
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

} // namespace test_files
