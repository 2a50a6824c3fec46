#!/bin/bash
# What --trace costs: the wall time of a 1 kHz pendulum controller run for
# VIRTUAL (default 30s) of virtual time, with and without a trace, the best
# of RUNS (default 5) interleaved runs of each; and the trace's size per
# 1,000 control cycles. Prints figures and their ratio, asserts nothing.
#   bench/trace_overhead.sh [BUILD_DIR]
set -euo pipefail
build=${1:-build}
runs=${RUNS:-5}
virtual=${VIRTUAL:-30s}
trace=$(mktemp --suffix=.mcap)
trap 'rm -f "$trace"' EXIT

wall() { # prints the wall seconds tcs-run ARGS... took
	local s e
	s=$(date +%s%N)
	"$build/tools/tcs-run" -q -d "$virtual" "$@" -- "$build/examples/pendulum_pd" >/dev/null 2>&1
	e=$(date +%s%N)
	echo $(((e - s) / 1000))
}
best_plain=0 best_traced=0
for ((i = 0; i < runs; i++)); do
	p=$(wall)
	t=$(wall -t "$trace")
	((best_plain == 0 || p < best_plain)) && best_plain=$p
	((best_traced == 0 || t < best_traced)) && best_traced=$t
done
cycles=$("$build/tools/trace/tcs-trace" summary --json "$trace" | python3 -c 'import json,sys; print(json.load(sys.stdin)["controllers"][0]["cycles"])')
bytes=$(stat -c %s "$trace")
awk -v p="$best_plain" -v t="$best_traced" -v b="$bytes" -v c="$cycles" -v n="$runs" 'BEGIN {
	printf "untraced run (best of %d)   %8.3f s\n", n, p / 1e6
	printf "traced run (best of %d)     %8.3f s   ratio %.3f (%+.1f %%)\n", n, t / 1e6, t / p, 100 * (t / p - 1)
	printf "wall cost per 1000 cycles  %8.3f ms\n", (t - p) / 1e3 / c * 1000
	printf "trace size                 %8.0f KB for %d cycles: %.0f KB per 1000 cycles\n", b / 1e3, c, b / 1e3 / c * 1000
}'
