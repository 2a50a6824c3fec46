// The fuzz target for records (tcs-run --replay FILE): an input is read as a
// record (trace/record.h) from memory. A record comes from anyone's disk, so
// what the reader accepts must be what a replay can take without a check of
// its own: journal entries of a kind the preload knows, controllers numbered
// from 1, a positive step and CPU scale; and what it refuses, one line
// naming the file. Its seeds are records as --record writes them (a
// settings message, journals, commands; uncompressed), one cut in half, and
// one without settings: a plain trace.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_target.h"
#include "mcap_writer.h"
#include "record.h"

namespace {

using tcs_fuzz::check;

// A record as tcs-run --record writes one (its three topics, the JSON as
// Trace writes it), uncompressed so that mutations reach the JSON, in
// memory.
std::string written_record(int cycles, bool settings)
{
	return tcs_fuzz::written_file([&](const std::string &path) {
		tcs::McapWriter w(tcs::McapWriterOptions{ .chunk_size = 400, .compression = tcs::McapCompression::none });
		if (!w.open(path, "", "tcs").ok())
			return;
		auto run = w.add_channel("/tcs/record/run", 0);
		auto journal = w.add_channel("/tcs/record/journal", 0);
		auto device = w.add_channel("/tcs/device", 0);
		if (!run.ok() || !journal.ok() || !device.ok())
			return;
		tcs::Record r;
		r.cpu_scale = 6;
		r.step_ns = 1000000;
		r.seed = 18446744073709551557ull;
		r.program = { "pendulum_pd", "--work-us", "300" };
		r.devices = { "/dev/tcs/pendulum/state", "/dev/tcs/pendulum/torque" };
		if (settings)
			(void)w.write(*run, 0, 0, tcs::record_run_json(r));
		for (int i = 0; i < cycles; i++) {
			std::string v = std::to_string(1000000LL * i);
			std::string entries = "[1,0,0," + v + "10,0],[5,0,0," + v + "20,652],[4,6,0," + v + "30,0],[2,0,0," +
					      v + "40,1],[4,2,0," + v + "50,0],[6,0,0," + v + "90,0]";
			(void)w.write(*journal, uint64_t(i), uint64_t(i),
				      "{\"controller\":1,\"entries\":[" + entries + (i + 1 == cycles ? ",[7,0,0,1,0]" : "") + "]}");
			(void)w.write(*device, uint64_t(i), uint64_t(i),
				      "{\"controller\":1,\"path\":\"/dev/tcs/pendulum/torque\",\"v_ns\":" + v +
					      "30,\"values\":[" + std::to_string(i) + ".5,-0],\"malformed\":" +
					      (i % 7 == 3 ? "true" : "false") + "}");
		}
		(void)w.close();
	});
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	auto r = tcs::read_record_bytes("fuzz", std::string(reinterpret_cast<const char *>(data), size));
	if (!r.ok()) {
		const std::string &e = r.error().message;
		check(e.rfind("fuzz: ", 0) == 0 && e.find('\n') == std::string::npos);
		return 0;
	}
	check(r->cpu_scale > 0 && std::isfinite(r->cpu_scale) && r->step_ns > 0);
	check(!r->seed || *r->seed != 0);
	for (const auto &[controller, entries] : r->journals) {
		check(controller >= 1);
		for (const tcs_journal_entry &e : entries)
			check(e.kind >= 1 && e.kind < TCS_J_KINDS);
	}
	for (const auto &[controller, commands] : r->commands)
		check(controller >= 1);
	for (const auto &[controller, scale] : r->scales)
		check(controller >= 1 && scale > 0 && std::isfinite(scale));
	return 0;
}

const char *tcs_fuzz_name()
{
	return "record_fuzz";
}

std::vector<std::string> tcs_fuzz_seeds()
{
	std::string record = written_record(60, true);
	return { record, record.substr(0, record.size() / 2), written_record(3, true), written_record(5, false) };
}

std::vector<std::string> tcs_fuzz_tokens()
{
	return { "\"seed\":\"", "18446744073709551616", "-1", "[0,0,0,0,0]", "[8,0,0,0,0]", "\"entries\":[",
		 "\"cpu_scale\":0", "\"step_ns\":-1", "\"controller\":0", "1e999" };
}

// The MCAP layer is trace_reader's to fuzz: the generic mutations and the
// tokens reach the JSON in these uncompressed seeds.
bool tcs_fuzz_mutate(std::string &, tcs_fuzz::Rng &)
{
	return false;
}
