// The writer tests' sample messages (see mcap_sample.h).
#include "mcap_sample.h"

#include <csetjmp>
#include <cstdarg>
#include <cstddef>

extern "C" {
#include <cmocka.h>
}

#include "result_checks.h"

namespace mcap_check {

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

} // namespace mcap_check
