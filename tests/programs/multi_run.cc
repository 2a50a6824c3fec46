// multi_run MODE DURATION_MS 'PROGRAM ARGS' 'PROGRAM ARGS'...: runs several
// controllers under one coordinator (each on its own virtual CPU), as the
// scenario files of a later release will, and prints one line of figures
// per controller. Arguments are split on spaces.
#include <cstdio>
#include <cstring>
#include <sstream>

#include "coordinator.h"
#include "preload_path.h"
#include "program_check.h"

int main(int argc, char **argv)
{
	if (argc < 4) {
		std::fprintf(stderr, "usage: multi_run cpu|lockstep DURATION_MS 'PROGRAM ARGS'...\n");
		return 2;
	}
	tcs::CoordinatorConfig cfg;
	cfg.mode = std::strcmp(argv[1], "lockstep") == 0 ? TCS_MODE_LOCKSTEP : TCS_MODE_CPU;
	cfg.duration_ns = std::atoll(argv[2]) * 1000000LL;
	auto preload = tcs::find_preload();
	if (!preload) {
		std::fprintf(stderr, "multi_run: %s\n", preload.error().message.c_str());
		return 2;
	}
	cfg.preload = *preload;
	auto co = tcs::Coordinator::create(cfg);
	if (!co)
		return 2;
	for (int i = 3; i < argc; i++) {
		tcs::ControllerSpec spec;
		std::istringstream words(argv[i]);
		for (std::string w; words >> w;)
			spec.argv.push_back(w);
		auto path = tcs::resolve_program(spec.argv[0]);
		if (!path)
			return 2;
		spec.path = *path;
		if (auto s = (*co)->add_controller(spec); !s) {
			std::fprintf(stderr, "multi_run: %s\n", s.error().message.c_str());
			return 2;
		}
	}
	auto r = (*co)->run();
	if (!r)
		return 2;
	for (const auto &c : r->controllers)
		std::printf("controller=%d periodic=%llu misses=%llu virtual_ns=%lld charged_ns=%lld\n", c.id,
			    (unsigned long long)c.periodic_waits, (unsigned long long)c.deadline_misses,
			    (long long)c.virtual_ns, (long long)c.charged_ns);
	return 0;
}
