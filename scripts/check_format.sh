#!/usr/bin/env bash
# Checks that the C++ files of the repository are formatted as .clang-format says (clang-format 14,
# Debian 12's). Files listed in scripts/format_pending.txt (the files that predate the check) are
# not checked yet; every other file is, new files included. Formatting a pending file: run
# `scripts/check_format.sh --fix FILE...` and remove it from the list in the same commit.
# Prints the files that are not formatted and exits 1.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--fix" ]; then
  shift
  [ $# -gt 0 ] || { echo "usage: scripts/check_format.sh [--fix FILE...]" >&2; exit 2; }
  clang-format -i "$@"
  exit 0
fi
pending=scripts/format_pending.txt
mapfile -t files < <(git ls-files '*.cpp' '*.h' '*.hpp' '*.cc' | grep -vxF -f <(grep -v '^#' "$pending"))
bad=()
for f in "${files[@]}"; do
  clang-format --dry-run --Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
stale=()
while read -r f; do
  [ -z "$f" ] || [ "${f:0:1}" = "#" ] || [ -e "$f" ] || stale+=("$f")
done < "$pending"
status=0
if [ ${#bad[@]} -ne 0 ]; then
  echo "check_format: ${#bad[@]} file(s) not formatted (scripts/check_format.sh --fix FILE...):"
  printf '  %s\n' "${bad[@]}"
  status=1
fi
if [ ${#stale[@]} -ne 0 ]; then
  echo "check_format: $pending names file(s) that no longer exist:"
  printf '  %s\n' "${stale[@]}"
  status=1
fi
[ $status -ne 0 ] || echo "check_format: ${#files[@]} C++ files formatted ($(grep -vc '^#' "$pending") pending)"
exit $status
