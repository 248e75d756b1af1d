#!/usr/bin/env bash
# Sets up, builds (release preset) and runs the reference case: today the modal analysis of the
# thesis's two-beam joint (stuck contact), printing the lowest frequencies and writing the mode
# shapes as VTU files for ParaView into out/reference/.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
cmake --preset release
cmake --build --preset release --target stickslip
mkdir -p out/reference
./build/release/src/cli/stickslip modes --arrangement butt --modes 8 -o out/reference "$@"
