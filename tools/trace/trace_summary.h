// The figures a user needs to decide whether a controller keeps its
// deadlines (docs/DESIGN.md §6), computed from a loaded trace, and their two
// renderings: text for people, JSON for scripts.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "trace_data.h"

namespace tcs {

// Percentiles of a set of durations (ns); all zero when there are none.
struct Spread {
	size_t count = 0;
	int64_t min = 0, p50 = 0, p99 = 0, max = 0;
};
Spread spread_of(std::vector<int64_t> values);

struct ControllerSummary {
	const TraceController *info = nullptr;
	// The loop: its timed waits, absolute ones if it uses any (a periodic
	// loop), else relative ones (a loop paced by sleeps).
	bool periodic = false;
	uint64_t cycles = 0;
	double rate_hz = 0;          // cycles per second of virtual time between the first and last
	int64_t asked_period = 0;    // periodic: the median step between its deadlines
	Spread period;               // between successive wake-ups
	uint64_t misses = 0;         // periodic: waits asked for a deadline already past
	uint64_t preemptions = 0;
	Spread overshoot;            // real CPU beyond the budget, per preemption
	int64_t charged_ns = 0;      // virtual CPU charged
	int64_t cpu_ns = 0;          // real CPU used in its slices, tcs's hooks included
	int64_t span_ns = 0;         // virtual time from its first slice to its last
	int64_t start_ns = 0;        // where its first slice began (a late joiner: > 0)
	int64_t computing_ns = 0;    // virtual time that passed while it ran
	uint64_t malformed_commands = 0;
};

struct RunSummary {
	std::string path;
	bool truncated = false;
	int64_t virtual_ns = 0, wall_ns = 0;
	uint64_t steps = 0;
	Spread step_cost;
	std::vector<ControllerSummary> controllers;
	std::vector<TraceWire> wires;
	// Σ|virtual time that passed while computing − CPU charged| / Σ charged,
	// over all controllers: 0 when computation costs exactly its CPU, 1
	// when it is free (lockstep).
	double timing_error = 0;
	// CPU the controllers used that tcs did not charge (its hooks' own
	// cost), as a fraction of what they used.
	double uncharged = 0;
};

RunSummary summarize(const TraceData &t);
std::string summary_text(const RunSummary &s);
std::string summary_json(const RunSummary &s);

} // namespace tcs
