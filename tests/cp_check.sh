#!/bin/sh
# The layer-order solver against Flat-Folder's own results on real crease
# patterns: $SUMI_SHARED/data/cp (default ../shared from the repository),
# skipped cleanly when absent. Each pattern's per-component state counts
# (`sumi fold --count`, capped at 10000 as Flat-Folder's batch run was)
# must equal states.csv's as multisets; every pattern in unsatisfiable/
# must be refused. Ends with "N passed, N failed[, N skipped]".
#
#   sh tests/cp_check.sh SUMI [MAX_VARIABLES]
#
# MAX_VARIABLES (default: no limit) leaves out the rows with more face
# pairs, so `make test` can run the fast part.

SUMI=$1
MAX=${2:-0}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
SHARED=${SUMI_SHARED:-../shared}
case "$SHARED" in /*) ;; *) SHARED="$ROOT/$SHARED" ;; esac
DATA="$SHARED/data/cp"
TMP=${TMPDIR:-/tmp}/sumi-cp.$$
passed=0; failed=0; skipped=0
trap 'rm -f "$TMP"' EXIT

if [ ! -f "$DATA/states.csv" ]; then
  echo "0 passed, 0 failed, 1 skipped"
  exit 0
fi

# Sorted counts, one a line: ours from `sumi fold --count`, Flat-Folder's
# from the |c0|c1|...| column less its first entry (the forced orders).
ours() { sed -n 's/.* \([0-9][0-9]*\) states, .*/\1/p' "$1" | sort -n | tr '\n' ' '; }
theirs() { echo "$1" | tr '|' '\n' | grep . | sed 1d | sort -n | tr '\n' ' '; }

# Read from the end of each row: titles may hold commas.
tail -n +2 "$DATA/states.csv" | awk -F, '{ print $1, $(NF-11), $(NF-2) }' > "$TMP.rows"
while read -r num vars counts; do
  file=$(ls "$DATA/${num}_"*.fold 2>/dev/null | head -1)
  if [ -z "$file" ] || { [ "$MAX" -gt 0 ] && [ "$vars" -gt "$MAX" ]; }; then
    skipped=$((skipped + 1)); continue
  fi
  if "$SUMI" fold "$file" --count > "$TMP" 2>&1 && [ "$(ours "$TMP")" = "$(theirs "$counts")" ]; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
    echo "FAIL cp/$num: counts [$(ours "$TMP")] want [$(theirs "$counts")]"
    grep error "$TMP" | head -3 | sed 's/^/  /'
  fi
done < "$TMP.rows"
rm -f "$TMP.rows"

for file in "$DATA"/unsatisfiable/*.fold; do
  [ -e "$file" ] || continue
  if ! "$SUMI" fold "$file" > "$TMP" 2>&1 && grep -q "no valid layer order" "$TMP"; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1)); echo "FAIL cp/unsatisfiable/$(basename "$file"): not refused"
  fi
done

if [ "$skipped" -gt 0 ]; then echo "$passed passed, $failed failed, $skipped skipped"
else echo "$passed passed, $failed failed"; fi
[ "$failed" -eq 0 ]
