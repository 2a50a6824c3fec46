// entropy_cxx: the clocks and the system's randomness as a C++ program
// meets them (std::chrono, std::random_device on /dev/urandom, an
// ifstream of it, a std::mt19937 seeded from it), for --seed and --epoch:
// a run that repeats prints the same bytes.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <random>
#include <thread>

int main()
{
	std::this_thread::sleep_for(std::chrono::milliseconds(10));
	auto steady = std::chrono::steady_clock::now().time_since_epoch();
	auto system = std::chrono::system_clock::now().time_since_epoch();
	std::printf("steady_ns=%lld\nsystem_ns=%lld\n",
		    (long long)std::chrono::duration_cast<std::chrono::nanoseconds>(steady).count(),
		    (long long)std::chrono::duration_cast<std::chrono::nanoseconds>(system).count());
	// (The default random_device may use the RDRAND instruction, which
	// nothing but the CPU sees: a file is named.)
	std::random_device rd("/dev/urandom");
	std::printf("random_device=%08x%08x\n", rd(), rd());
	std::mt19937_64 gen(((uint64_t)rd() << 32) | rd());
	std::printf("mt19937=%016llx\n", (unsigned long long)gen());
	std::ifstream in("/dev/urandom", std::ios::binary);
	unsigned char b[8] = {};
	in.read(reinterpret_cast<char *>(b), sizeof b);
	std::printf("ifstream=");
	for (unsigned char c : b)
		std::printf("%02x", c);
	std::printf("\n");
	return 0;
}
