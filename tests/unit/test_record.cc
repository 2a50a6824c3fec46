// Unit tests for trace/record: a record written as tcs-run --record writes
// one (Trace with the record's topics) reads back whole, settings (a seed
// above 2^63 too), each controller's journal in order and its commands; a
// record cut short reads as far as it goes; what is not a record, or holds
// entries a replay could not take, is refused with one line naming the file.
#include <csetjmp>
#include <cstdarg>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

// (Before cmocka.h, whose fail() a stream header's would meet.)
#include "record.h"
#include "trace.h"

extern "C" {
#include <cmocka.h>
}

#include "result_checks.h"

#include "test_files.h"

namespace {

using namespace test_files;

tcs::Record settings()
{
	tcs::Record r;
	r.cpu_scale = 6;
	r.step_ns = 1000000;
	r.mono_origin_ns = 100000000000000;
	r.real_origin_ns = 1795694412580045744;
	r.tai_origin_ns = 1795694449580045744;
	r.seed = 18446744073709551557ull; // above 2^63: JSON's integers do not hold it
	r.slack = false;
	r.duration_ns = 2500000000;
	r.program = { "pendulum_pd", "--work-us", "300", "a \"quoted\" arg" };
	r.devices = { "/dev/tcs/pendulum/state", "/dev/tcs/pendulum/torque" };
	return r;
}

tcs_journal_entry entry(uint16_t kind, uint16_t type, int64_t value, int64_t arg = 0)
{
	tcs_journal_entry e = {};
	e.kind = kind;
	e.type = type;
	e.value = value;
	e.arg = arg;
	return e;
}

const std::string kTorque = "/dev/tcs/pendulum/torque";

using Entries = std::vector<tcs_journal_entry>;

// A record of two controllers, the first's journal in two batches; written
// by the caller (as the coordinator does on a core of its own) or by the
// trace's thread.
std::string write_record(const std::string &name, bool by_caller = false)
{
	std::string path = test_path(name);
	tcs::Trace t;
	CHECK_OK(t.open(path, tcs::TraceWriting{ .by_caller = by_caller }, true));
	t.record_run(tcs::record_run_json(settings()));
	t.journal(1, Entries{ entry(TCS_J_CLOCK, 0, 10), entry(TCS_J_CHARGE, TCS_MSG_DEV_OPEN, 20) });
	t.journal(2, Entries{ entry(TCS_J_READ, 0, 30, 652) });
	t.command(1, kTorque, 40, std::vector<double>{ 1.5, -0.25 }, false);
	t.command(1, kTorque, 50, {}, true);
	t.journal(1, Entries{ entry(TCS_J_STOP, 0, 1000000), entry(TCS_J_CPU, 0, 7, 0), entry(TCS_J_EXIT, 0, 2000000) });
	CHECK_OK(t.close());
	return path;
}

void check_whole(const std::string &path);

void test_a_record_reads_back_whole(void **)
{
	for (bool by_caller : { false, true })
		check_whole(write_record(by_caller ? "whole-by-caller.mcap" : "whole.mcap", by_caller));
}

void check_whole(const std::string &path)
{
	tcs::Record r = MUST(tcs::read_record(path));
	tcs::Record want = settings();
	assert_true(r.cpu_scale == 6.0);
	assert_int_equal(r.step_ns, want.step_ns);
	assert_int_equal(r.mono_origin_ns, want.mono_origin_ns);
	assert_int_equal(r.real_origin_ns, want.real_origin_ns);
	assert_int_equal(r.tai_origin_ns, want.tai_origin_ns);
	assert_true(r.seed && *r.seed == *want.seed);
	assert_false(r.slack);
	assert_int_equal(r.duration_ns, 2500000000);
	assert_true(r.program == want.program);
	assert_true(r.devices == want.devices);
	assert_false(r.truncated);

	assert_int_equal(r.journals.size(), 2);
	const auto &one = r.journals.at(1);
	const uint16_t kinds[] = { TCS_J_CLOCK, TCS_J_CHARGE, TCS_J_STOP, TCS_J_CPU, TCS_J_EXIT };
	const int64_t values[] = { 10, 20, 1000000, 7, 2000000 };
	assert_int_equal(one.size(), 5);
	for (size_t i = 0; i < one.size(); i++) {
		assert_int_equal(one[i].kind, kinds[i]);
		assert_int_equal(one[i].value, values[i]);
	}
	assert_int_equal(one[1].type, TCS_MSG_DEV_OPEN);
	assert_int_equal(r.journals.at(2).at(0).arg, 652);

	const auto &commands = r.commands.at(1);
	assert_int_equal(commands.size(), 2);
	assert_string_equal(commands[0].path.c_str(), kTorque.c_str());
	assert_int_equal(commands[0].v, 40);
	assert_true(commands[0].values == (std::vector<double>{ 1.5, -0.25 }));
	assert_false(commands[0].malformed);
	assert_true(commands[1].malformed && commands[1].values.empty());
}

void test_a_record_without_a_seed_has_none(void **)
{
	std::string path = test_path("unseeded.mcap");
	tcs::Record s = settings();
	s.seed.reset();
	tcs::Trace t;
	CHECK_OK(t.open(path, {}, true));
	t.record_run(tcs::record_run_json(s));
	CHECK_OK(t.close());
	assert_false(MUST(tcs::read_record(path)).seed.has_value());
}

void test_a_record_cut_short_reads_as_far_as_it_goes(void **)
{
	// A run killed mid-way: its record stops in a chunk (the settings,
	// written first, are in the first).
	std::string path = test_path("long.mcap");
	tcs::Trace t;
	CHECK_OK(t.open(path, {}, true));
	t.record_run(tcs::record_run_json(settings()));
	const size_t batches = 200, per = 1000;
	for (size_t b = 0; b < batches; b++) {
		std::vector<tcs_journal_entry> batch;
		for (size_t i = 0; i < per; i++)
			batch.push_back(entry(TCS_J_CLOCK, 0, (int64_t)(b * per + i) * 977));
		t.journal(1, std::move(batch));
	}
	CHECK_OK(t.close());
	std::string whole = slurp(path);
	std::string cut = test_path("cut.mcap");
	spit(cut, whole.substr(0, whole.size() * 6 / 10));
	tcs::Record r = MUST(tcs::read_record(cut));
	assert_true(r.truncated);
	const auto &got = r.journals.at(1);
	assert_true(got.size() > 0 && got.size() < batches * per);
	for (size_t i = 0; i < got.size(); i++)
		assert_int_equal(got[i].value, (int64_t)i * 977); // in order, none lost before the cut
	assert_true(r.program == settings().program);
}

void test_what_is_not_a_record_is_refused(void **)
{
	std::string plain = test_path("plain.mcap");
	tcs::Trace t;
	CHECK_OK(t.open(plain, {}, false));
	t.command(1, kTorque, 40, std::vector<double>{ 1.0 }, false);
	CHECK_OK(t.close());
	auto r = tcs::read_record(plain);
	assert_false(r.ok());
	assert_string_equal(r.error().message.c_str(), (plain + ": not a record (a trace written without --record)").c_str());

	std::string missing = test_path("missing.mcap");
	r = tcs::read_record(missing);
	assert_false(r.ok());
	assert_string_equal(r.error().message.c_str(), (missing + ": No such file or directory").c_str());
}

// A record whose run message is json, written raw (no Trace checks it).
tcs::Result<tcs::Record> record_with(const std::string &name, const std::string &run_json,
				     const std::string &journal_json)
{
	std::string path = test_path(name);
	tcs::McapWriter w;
	CHECK_OK(w.open(path, "", "tcs"));
	uint16_t run = MUST(w.add_channel("/tcs/record/run", 0));
	uint16_t journal = MUST(w.add_channel("/tcs/record/journal", 0));
	CHECK_OK(w.write(run, 0, 0, run_json));
	if (!journal_json.empty())
		CHECK_OK(w.write(journal, 0, 0, journal_json));
	CHECK_OK(w.close());
	return tcs::read_record(path);
}

void test_entries_a_replay_could_not_take_are_refused(void **)
{
	const std::string run = tcs::record_run_json(settings());
	const struct {
		const char *run, *journal, *said;
	} cases[] = {
		{ nullptr, R"({"controller":1,"entries":[[0,0,0,5,0]]})", "a journal entry that is not" },
		{ nullptr, R"({"controller":1,"entries":[[8,0,0,5,0]]})", "a journal entry that is not" },
		{ nullptr, R"({"controller":1,"entries":[[1,0,0,5]]})", "a journal entry that is not" },
		{ nullptr, R"({"controller":1,"entries":[[1,70000,0,5,0]]})", "a journal entry that is not" },
		{ nullptr, R"({"controller":1,"entries":[[1,0,0,5.5,0]]})", "a journal entry that is not" },
		{ nullptr, R"({"controller":0,"entries":[]})", "a journal message without its controller" },
		{ nullptr, R"({"controller":1})", "a journal message without its controller" },
		{ R"({"cpu_scale":0,"step_ns":1000000})", "", "the record's settings are not valid" },
		{ R"({"cpu_scale":1,"step_ns":0})", "", "the record's settings are not valid" },
		{ R"({"cpu_scale":1,"step_ns":1000000,"seed":"-1"})", "", "the record's seed is not a whole number" },
		{ R"({"cpu_scale":1,"step_ns":1000000,"duration_ns":-5})", "", "the record's duration_ns is not valid" },
		{ R"({"cpu_scale":1,"step_ns":1000000,"seed":"18446744073709551616"})", "",
		  "the record's seed is not a whole number" },
		{ R"({"cpu_scale":1,)", "", "/tcs/record/run: at byte" },
	};
	int n = 0;
	for (const auto &c : cases) {
		std::string name = "bad" + std::to_string(n++) + ".mcap";
		auto r = record_with(name, c.run ? c.run : run, c.journal);
		assert_false(r.ok());
		const std::string &e = r.error().message;
		if (e.find(c.said) == std::string::npos || e.rfind(test_path(name) + ": ", 0) != 0) {
			print_error("case %d: '%s' does not say '%s'\n", n - 1, e.c_str(), c.said);
			fail();
		}
	}
}

} // namespace

int main(void)
{
	if (!test_dir_open("tcs-record-test"))
		return 1;
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_a_record_reads_back_whole),
		cmocka_unit_test(test_a_record_without_a_seed_has_none),
		cmocka_unit_test(test_a_record_cut_short_reads_as_far_as_it_goes),
		cmocka_unit_test(test_what_is_not_a_record_is_refused),
		cmocka_unit_test(test_entries_a_replay_could_not_take_are_refused),
	};
	int failed = cmocka_run_group_tests(tests, nullptr, nullptr);
	test_dir_close();
	return failed;
}
