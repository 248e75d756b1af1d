#!/usr/bin/env bash
# What CI runs after the README's test command (scripts/test.sh), so that what the presets promise
# holds on main:
#   1. the formatting of the C++ files (scripts/check_format.sh, clang-format 14);
#   2. the `dev` preset: warnings are errors, assertions on (-O1 -g), the whole suite.
#   3. the `asan` preset: Address + UndefinedBehavior sanitizers (-O1 -g), the whole suite but the one
#      test that only exercises a defect inside Debian's libgmsh 4.8 (README.md, "Developing").
# Measured on this kind of machine (2 cores): the asan build about 20 min from scratch, its suite
# 7 min (main b25e0f5, 2026-11-26); the whole CI run stays well inside its 90 min.
# Needs what scripts/setup.sh installs (run scripts/test.sh, or setup.sh, first).
set -euo pipefail
cd "$(dirname "$0")/.."
export STICKSLIP_REQUIRE_TOOLS=1
./scripts/check_format.sh
cmake --preset dev
cmake --build --preset dev
ctest --preset dev
cmake --preset asan
cmake --build --preset asan
ctest --preset asan
