#!/usr/bin/env bash
# Sets up, builds (release preset) and runs the reference case of the thesis (examples/02): the
# two-beam friction joint, Craig–Bampton reduction, harmonic balance around the 4th mode of the
# stuck assembly for three preloads, and stress recovery on the full meshes. Results and plots
# go to out/reference/ (see docs/output-files.md).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
cmake --preset release
cmake --build --preset release --target stickslip
mkdir -p out/reference
./build/release/src/cli/stickslip modes --arrangement butt --modes 8 -o out/reference/modes
./build/release/src/cli/stickslip run examples/02_two_beam_joint/case.yaml -o out/reference "$@"
echo "reference case done: out/reference (frf_study.png, preload_*/, modes/modes.vtu)"
