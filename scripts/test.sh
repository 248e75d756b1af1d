#!/usr/bin/env bash
# Sets up, builds (release preset) and runs the whole test suite. This is the command README.md
# gives and .ci/run calls.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
# setup.sh installed ccx, gnuplot and scipy: a test that needs one fails instead of skipping
# (tests/required_tool.h).
export STICKSLIP_REQUIRE_TOOLS=1
cmake --preset release
cmake --build --preset release
ctest --preset release "$@"
