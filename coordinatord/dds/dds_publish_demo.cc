// dds_publish_demo DOMAIN N: publishes N virtual milliseconds of a swinging
// pendulum's clock and joint state through RosPublisher, one per real
// millisecond, for clock_listen or a ROS 2 tool to receive.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>

#include "ros_publisher.h"

namespace {

bool parse(const char *s, long max, long &out)
{
	char *end;
	errno = 0;
	out = std::strtol(s, &end, 10);
	return errno == 0 && end != s && *end == '\0' && out >= 0 && out <= max;
}

} // namespace

int main(int argc, char **argv)
{
	long domain, n;
	if (argc != 3 || !parse(argv[1], 232, domain) || !parse(argv[2], 1000000000, n)) {
		std::fprintf(stderr, "usage: dds_publish_demo DOMAIN N\n");
		return 2;
	}
	auto pub = tcs::RosPublisher::create(static_cast<uint32_t>(domain), { "pendulum.hinge" });
	if (!pub) {
		std::fprintf(stderr, "dds_publish_demo: %s\n", pub.error().message.c_str());
		return 1;
	}
	// Volatile topics: what is written before a reader matches is lost.
	// This sees our writer match the reader; the reader matches our writer
	// on its own, maybe a moment later, so it may still miss a first sample
	// (as a ROS 2 node would): tests ask clock_listen for fewer than N.
	if (auto s = (*pub)->wait_for_subscriber(10'000'000'000); !s)
		std::fprintf(stderr, "dds_publish_demo: %s; publishing anyway\n", s.error().message.c_str());

	constexpr int64_t step_ns = 1'000'000;
	const double omega = 2 * M_PI / 2.0; // a 2 s period
	timespec next;
	clock_gettime(CLOCK_MONOTONIC, &next);
	for (long i = 1; i <= n; i++) {
		const int64_t t = i * step_ns;
		const double ts = t * 1e-9;
		const double position = 0.5 * std::cos(omega * ts);
		const double velocity = -0.5 * omega * std::sin(omega * ts);
		(*pub)->clock(t);
		(*pub)->joint_states(t, &position, &velocity, nullptr);
		next.tv_nsec += step_ns;
		if (next.tv_nsec >= 1'000'000'000) {
			next.tv_sec++;
			next.tv_nsec -= 1'000'000'000;
		}
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, nullptr);
	}
	std::printf("published %ld, dropped %llu\n", n, static_cast<unsigned long long>((*pub)->dropped()));
	return 0;
}
