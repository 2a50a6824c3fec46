#!/usr/bin/env bash
# The README's two commands. On a fresh Debian 12 machine (as root) this
# installs the Debian packages tcs needs, builds it, and then either runs
# the demo (the pendulum experiment under tcs-run in the built-in world),
# the whole test suite, or the performance suite (bench/run.py, which also
# wants libfaketime as a baseline).
#
#   tools/bootstrap.sh demo
#   tools/bootstrap.sh test
#   tools/bootstrap.sh bench [bench/run.py options]
#
# TCS_BUILD_DIR picks the build directory (default: build).
set -euo pipefail

cd "$(dirname "$0")/.."
what=${1:-}
if [[ $what != demo && $what != test && $what != bench ]]; then
	echo "usage: tools/bootstrap.sh demo|test|bench" >&2
	exit 2
fi

packages=(gcc g++ libc6-dev binutils pkg-config meson ninja-build python3 libcmocka-dev util-linux
	libode-dev libccd-dev libeigen3-dev libtomlplusplus-dev libzstd-dev gnuplot-nox
	cyclonedds-dev cyclonedds-tools
	libsdformat-dev libtinyxml2-dev libconsole-bridge-dev)
[[ $what == bench ]] && packages+=(faketime)
# Real programs nobody wrote for tcs, which the tests run under it.
[[ $what == test ]] && packages+=(rt-tests stress-ng coreutils)
# Stock bus tools, unmodified, on the scenario's CAN and I2C buses.
[[ $what == test ]] && packages+=(can-utils i2c-tools)
# Counting a lockstep round trip's system calls.
[[ $what == test ]] && packages+=(strace)
# The agent tests put an agent in a network namespace of its own.
[[ $what == test ]] && packages+=(iproute2)
# Stock bus tools the wire tests run unmodified on the emulated buses.
[[ $what == test ]] && packages+=(can-utils i2c-tools)
missing=()
for p in "${packages[@]}"; do
	dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
	if [[ $(id -u) != 0 ]]; then
		echo "bootstrap: these Debian packages are missing, and installing them needs root: ${missing[*]}" >&2
		exit 2
	fi
	echo "bootstrap: installing ${missing[*]}"
	export DEBIAN_FRONTEND=noninteractive
	apt-get update -qq
	apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# The official MCAP reader the tests check traces with (Node.js, npm registry).
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
	if [[ $(id -u) != 0 ]]; then
		echo "bootstrap: Node.js and npm are missing, and installing them needs root" >&2
		exit 2
	fi
	echo "bootstrap: installing nodejs npm"
	export DEBIAN_FRONTEND=noninteractive
	apt-get install -y -qq --no-install-recommends nodejs npm >/dev/null
fi
if [[ $what == test && ( ! -d tests/mcap/node_modules/@mcap/core ||
	! -d tests/mcap/node_modules/@foxglove/rosmsg2-serialization ) ]]; then
	echo "bootstrap: installing the MCAP and ROS 2 message readers for the tests (npm ci)"
	npm ci --prefix tests/mcap --no-audit --no-fund --loglevel=error >/dev/null
fi

build=${TCS_BUILD_DIR:-build}
[[ -f $build/build.ninja ]] || meson setup "$build" >/dev/null
ninja -C "$build" >/dev/null

if [[ $what == demo ]]; then
	run() {
		echo
		echo "\$ tcs-run $*"
		"$build/tools/tcs-run" "$@"
	}
	pd=$build/examples/pendulum_pd
	echo "The TCS paper's experiment in the built-in world: a pendulum and a 1 kHz controller that"
	echo "swings it up and balances it (examples/pendulum_pd.c, a plain C program)."
	run -- "$pd" --seconds 10 --work-us 50
	echo
	echo "The same binary with a heavier control law (300 us of this CPU per cycle) on a target"
	echo "CPU 6 times slower: the loop falls far below 1 kHz and the pendulum falls, as on the robot."
	run --cpu-scale 6 -- "$pd" --seconds 10 --work-us 300
	echo
	echo "Lockstep, as today's simulators run controllers: computation is free, so the same"
	echo "overloaded controller looks perfect."
	run --cpu-scale 6 -m lockstep -- "$pd" --seconds 10 --work-us 300
	exit 0
fi

if [[ $what == bench ]]; then
	shift
	exec python3 bench/run.py --build "$build" "$@"
fi

status=0
meson test -C "$build" --print-errorlogs || status=$?
# The process tests again as on a machine where tcs's fast paths are off
# (no TSC, slow CPU-clock system calls: tests/meson.build, "slowclock").
echo
echo "bootstrap: the process tests again, as on a machine without tcs's fast paths (--setup slowclock)"
meson test -C "$build" --print-errorlogs --setup slowclock --suite process || status=$?
# Closing lines any CI can read: test functions passed, failed and skipped
# in each setup, then each skipped function and its reason (tools/
# test_summary.py: a skip inside a file meson calls OK is counted too).
echo
python3 tools/test_summary.py "$build/meson-logs/testlog.json" "$build/meson-logs/testlog-slowclock.json" || status=$?
exit $status
