#!/usr/bin/env bash
# What CI runs after the README's test command (scripts/test.sh), so that what the presets promise
# holds on main:
#   1. the formatting of the C++ files (scripts/check_format.sh, clang-format 14);
#   2. the `dev` preset: warnings are errors, assertions on (-O1 -g), the whole suite.
# The `asan` preset (Address + UB sanitizers) is not in CI yet: on main f8a9fb9 its build took
# 20 min and its suite 6 min on this machine (2026-11-25), 700 of 702 tests clean, the two others
# failing inside libgmsh (README.md, "Developing": the preset now works around both); it goes in
# once a whole run on main is clean. Run it before a change to memory handling:
#   cmake --preset asan && cmake --build --preset asan && ctest --preset asan
# Needs what scripts/setup.sh installs (run scripts/test.sh, or setup.sh, first).
set -euo pipefail
cd "$(dirname "$0")/.."
export STICKSLIP_REQUIRE_TOOLS=1
./scripts/check_format.sh
cmake --preset dev
cmake --build --preset dev
ctest --preset dev
