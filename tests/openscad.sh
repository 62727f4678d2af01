#!/bin/sh
# The same solids as OpenSCAD: each tests/openscad/x.npr has a twin x.scad,
# the same program as an OpenSCAD user writes it. OpenSCAD exports its
# solid (openscad -o x.stl), sumi its own (sumi export), and
# tests/tools/stlcmp.py compares their volumes and bounding boxes: within
# 1e-4 of the larger unless the case's line "// tolerance: --volume R --box
# B" allows more (round shapes: sumi's are patches cut 32 a side, the
# .scad's polygons of $fn = 96); sumi's must be closed and consistently
# oriented, every edge met once each way. Skips every case when openscad is not
# installed. Ends with "N passed, N failed[, N skipped]".
#
#   sh tests/openscad.sh SUMI

SUMI=$1
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=${OUT:-$ROOT/build/test-out/openscad}
rm -rf "$OUT"; mkdir -p "$OUT"
passed=0; failed=0; skipped=0
for f in "$ROOT"/tests/openscad/*.npr; do
  name=$(basename "$f" .npr)
  if ! command -v openscad >/dev/null 2>&1; then skipped=$((skipped + 1)); continue; fi
  tol=$(head -3 "$f" | sed -n 's|^// tolerance: *||p')
  if ! openscad -o "$OUT/$name.scad.stl" "$ROOT/tests/openscad/$name.scad" >"$OUT/$name.scad.log" 2>&1; then
    failed=$((failed + 1)); echo "FAIL openscad/$name (openscad failed)"; tail -5 "$OUT/$name.scad.log"; continue
  fi
  if ! (cd "$ROOT/tests/openscad" && "$SUMI" export "$name.npr" -o "$OUT/$name.npr.stl") >"$OUT/$name.npr.log" 2>&1 ||
     [ -s "$OUT/$name.npr.log" ]; then
    failed=$((failed + 1)); echo "FAIL openscad/$name (sumi export failed or warned)"; head -5 "$OUT/$name.npr.log"; continue
  fi
  # shellcheck disable=SC2086
  if python3 "$ROOT/tests/tools/stlcmp.py" "$OUT/$name.scad.stl" "$OUT/$name.npr.stl" --closed $tol >"$OUT/$name.cmp" 2>&1; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1)); echo "FAIL openscad/$name"; sed 's/^/  /' "$OUT/$name.cmp"
  fi
done
if [ "$skipped" -gt 0 ]; then echo "$passed passed, $failed failed, $skipped skipped"
else echo "$passed passed, $failed failed"; fi
