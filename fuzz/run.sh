#!/usr/bin/env bash
# Runs one libFuzzer harness (docs/fuzzing.md):  fuzz/run.sh TARGET SECONDS [libFuzzer options]
# TARGET: inp harwell_boeing matrix_market dense_binary ansys_mapping case_file case_csv.
# Needs the fuzz build:  cmake --preset fuzz && cmake --build --preset fuzz
# New corpus entries go to build/fuzz/corpus/TARGET (fuzz/corpus/TARGET, the committed seeds, is
# read only); a crashing input goes to build/fuzz/artifacts/TARGET/ and stops the run.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
target="$1"; seconds="$2"; shift 2
build="$root/build/fuzz"
mkdir -p "$build/corpus/$target" "$build/artifacts/$target"
dict=()
[[ -f "$root/fuzz/dict/$target.dict" ]] && dict=("-dict=$root/fuzz/dict/$target.dict")
# One process on one core; a single allocation over 256 MB from an input of at most 4 kB is a
# size field believed before the data backs it; 10 s for one input is a hang.
exec "$build/fuzz/fuzz_$target" "$build/corpus/$target" "$root/fuzz/corpus/$target" \
  -max_total_time="$seconds" -rss_limit_mb=2048 -malloc_limit_mb=256 -timeout=10 -max_len=4096 \
  -artifact_prefix="$build/artifacts/$target/" -print_final_stats=1 "${dict[@]}" "$@"
