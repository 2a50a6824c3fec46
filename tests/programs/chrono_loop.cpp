// chrono_loop N PERIOD_MS: N iterations of std::this_thread::sleep_until on
// std::chrono::steady_clock, as a C++ controller would pace itself; prints
// the steady_clock time elapsed and system_clock's final time (ns), and the
// CPU the kernel had charged the process by then (kernel_cpu_ns: work.h).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "work.h"

int main(int argc, char **argv)
{
	if (argc != 3) {
		std::fprintf(stderr, "usage: chrono_loop N PERIOD_MS\n");
		return 2;
	}
	using namespace std::chrono;
	const int n = std::atoi(argv[1]);
	const auto period = milliseconds(std::atoi(argv[2]));
	const auto start = steady_clock::now();
	auto next = start;
	for (int i = 0; i < n; i++) {
		next += period;
		std::this_thread::sleep_until(next);
	}
	const auto elapsed = duration_cast<nanoseconds>(steady_clock::now() - start).count();
	const auto wall = duration_cast<nanoseconds>(system_clock::now().time_since_epoch()).count();
	const long long kernel = kernel_cpu_ns();
	std::printf("steady_elapsed_ns=%lld\nsystem_now_ns=%lld\nkernel_cpu_ns=%lld\n", (long long)elapsed, (long long)wall,
		    kernel);
	// And a relative sleep_for, which goes through nanosleep.
	const auto t0 = steady_clock::now();
	std::this_thread::sleep_for(milliseconds(250));
	std::printf("sleep_for_ns=%lld\n", (long long)duration_cast<nanoseconds>(steady_clock::now() - t0).count());
	return 0;
}
