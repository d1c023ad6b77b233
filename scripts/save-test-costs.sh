#!/usr/bin/env bash
# Writes tests/test_costs.txt from the timings ctest kept in build/ and build-asan/ (run both suites first).
# Each line: a ctest entry that took 2 s or more in either suite, then its seconds under the sanitizers and in
# release ("-": not run there). tests/CMakeLists.txt gives each its COST, so a fresh build's ctest, which has no
# timings of its own yet, starts the longest entries first (docs/design/reliability.md, "What CI spends its 40 minutes on").
set -euo pipefail
cd "$(dirname "$0")/.."
asan=build-asan/Testing/Temporary/CTestCostData.txt
release=build/Testing/Temporary/CTestCostData.txt
for f in "$asan" "$release"; do
  [ -f "$f" ] || { echo "save-test-costs: $f is missing: run that build's ctest first" >&2; exit 1; }
done
# ctest keeps the timings of entries that no longer exist (a renamed test, a suite made one entry): only the
# release build's current entries are written.
current="$(mktemp)"
trap 'rm -f "$current"' EXIT
ctest --test-dir build -N | sed -n 's/^ *Test *#[0-9]*: //p' >"$current"
{
  echo "# ctest entry, seconds under ASan + UBSan, seconds in release (- : not run there). Written by"
  echo "# scripts/save-test-costs.sh from the suites' own timings; only the order matters, not the values."
  awk 'FNR == 1 { file++ } file == 1 { exists[$1] = 1; next } /^---/ { nextfile }
       NF == 3 && ($1 in exists) { cost[$1, file - 1] = $3; names[$1] = 1 }
       END {
         for (n in names) {
           a = ((n, 1) in cost) ? cost[n, 1] : -1; r = ((n, 2) in cost) ? cost[n, 2] : -1
           if (a >= 2 || r >= 2)
             printf "%s %s %s\n", n, a < 0 ? "-" : sprintf("%.0f", a), r < 0 ? "-" : sprintf("%.0f", r)
         }
       }' "$current" "$asan" "$release" | sort
} > tests/test_costs.txt.new
mv tests/test_costs.txt.new tests/test_costs.txt
echo "tests/test_costs.txt: $(grep -vc '^#' tests/test_costs.txt) entries"
