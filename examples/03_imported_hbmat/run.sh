#!/usr/bin/env bash
# Makes the HBMAT-style matrices from example 02's mesh, then runs this example.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
stickslip="${STICKSLIP:-$here/../../build/release/src/cli/stickslip}"
"$stickslip" reduce "$here/../02_two_beam_joint/case.yaml" -o "$here" "$@"
"$stickslip" run "$here/case.yaml" "$@"
