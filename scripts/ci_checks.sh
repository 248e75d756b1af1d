#!/usr/bin/env bash
# What CI runs after the README's test command (scripts/test.sh), so that what the presets promise
# holds on main:
#   1. the formatting of every C++ file (scripts/check_format.sh, clang-format 14);
#   2. the `dev` preset: warnings are errors, assertions on (-O1 -g), the whole suite;
#   3. the `asan` preset: AddressSanitizer + UndefinedBehaviorSanitizer, the whole suite.
# Needs what scripts/setup.sh installs (run scripts/test.sh, or setup.sh, first).
set -euo pipefail
cd "$(dirname "$0")/.."
export STICKSLIP_REQUIRE_TOOLS=1
./scripts/check_format.sh
for preset in dev asan; do
  echo "ci_checks: preset $preset"
  cmake --preset "$preset"
  cmake --build --preset "$preset"
  ctest --preset "$preset"
done
