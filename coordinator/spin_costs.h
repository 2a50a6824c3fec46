// What a spin's calls cost natively (docs/DESIGN.md §2, spins in
// lockstep): a clock read, and an empty non-blocking read, measured on
// this machine at start-up; fixed nominal figures where a run must repeat
// (--epoch), since a measurement differs from run to run by a nanosecond.
#pragma once

#include <cstdint>

namespace tcs {

struct SpinCosts {
	int64_t clock_ns = 0; // a vDSO clock read
	int64_t read_ns = 0;  // a read(2) that finds nothing and does not wait
};

// The nominal figures: a vDSO clock read and a short system call on a
// current x86 machine.
constexpr SpinCosts kNominalSpinCosts{ 25, 500 };

// The most a user may set (the clock page holds 32 bits).
constexpr int64_t kMostSpinCost = 1000000;

// Measured here: the least of several batches (noise only adds).
SpinCosts measure_spin_costs();

} // namespace tcs
