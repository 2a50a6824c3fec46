/* threads_cxx: the timed waits of C++'s standard library, in virtual time.
 * Prints key=value lines (times in virtual ns from steady_clock) that a
 * test checks:
 *   cv_timeout_ns      condition_variable::wait_for(2 ms), nobody notifies
 *                      (another thread sleeps 20 ms meanwhile)
 *   cv_notified_ns     condition_variable::wait_until, notified at 1 ms
 *   future_timeout_ns  future::wait_for(3 ms) on a promise set at 5 ms
 *   future_ready_ns    the same future's wait() returning
 *   std::thread joins; the figures must not depend on the machine.
 * With each, *_cpu: the process's CPU by the kernel's clock (work.h: not
 * the CPU clock tcs answers, which would grow with an overcharge) from just
 * before its start was read to just after it ended. */
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <future>
#include <mutex>
#include <thread>
#include <time.h>

#include "work.h"

using namespace std::chrono;

static long long cpu()
{
	return kernel_cpu_ns();
}

int main()
{
	const auto t0 = steady_clock::now();
	auto since = [&] { return (long long)duration_cast<nanoseconds>(steady_clock::now() - t0).count(); };
	std::mutex m;
	std::condition_variable cv;
	bool flag = false;

	{
		std::thread sleeper([] { std::this_thread::sleep_for(milliseconds(20)); });
		std::unique_lock<std::mutex> lk(m);
		auto c0 = cpu();
		auto start = since();
		bool got = cv.wait_for(lk, milliseconds(2), [&] { return flag; });
		auto took = since() - start;
		std::printf("cv_timeout_result=%d cv_timeout_ns=%lld cv_timeout_cpu=%lld\n", got ? 1 : 0, took, cpu() - c0);
		lk.unlock();
		sleeper.join();
	}
	{
		auto c0 = cpu();
		auto start = since();
		std::thread notifier([&] {
			std::this_thread::sleep_for(milliseconds(1));
			std::lock_guard<std::mutex> g(m);
			flag = true;
			cv.notify_one();
		});
		std::unique_lock<std::mutex> lk(m);
		bool got = cv.wait_until(lk, steady_clock::now() + seconds(1), [&] { return flag; });
		auto took = since() - start;
		std::printf("cv_notified_result=%d cv_notified_ns=%lld cv_notified_cpu=%lld\n", got ? 1 : 0, took, cpu() - c0);
		lk.unlock();
		notifier.join();
	}
	{
		std::promise<int> p;
		std::future<int> f = p.get_future();
		auto c0 = cpu();
		auto start = since();
		std::thread setter([&] {
			std::this_thread::sleep_for(milliseconds(5));
			p.set_value(7);
		});
		auto st = f.wait_for(milliseconds(3));
		auto took = since() - start;
		std::printf("future_status=%s future_timeout_ns=%lld future_timeout_cpu=%lld\n",
			    st == std::future_status::timeout ? "timeout" : "other", took, cpu() - c0);
		f.wait();
		took = since() - start;
		std::printf("future_value=%d future_ready_ns=%lld future_ready_cpu=%lld\n", f.get(), took, cpu() - c0);
		setter.join();
	}
	return 0;
}
