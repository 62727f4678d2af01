#!/bin/sh
# Tiles: every scene in examples/ (so an example added later is covered
# too) rendered whole, then as tiles of two splits (3 rows of tiles; 2
# columns by 3 rows, whose columns do not fall on the renderer's 32-pixel
# screen tiles), each tile in its own process as a scheduler would run it,
# stitched by `sumi assemble`: the result must be byte-identical to the
# whole render. An animation (`// frames: A:B`) is checked at every frame,
# each tile process rendering its tile of all of them. Examples whose
# `// needs:` file is absent are skipped. Ends with "N passed, N failed".
#
#   sh tests/tiles.sh SUMI

SUMI=$1
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=${OUT:-$ROOT/build/test-out/tiles}
mkdir -p "$OUT"
passed=0; failed=0; skipped=0

# split_count SPLIT: how many tiles it has
split_count() { case $1 in *x*) echo $(( ${1%x*} * ${1#*x} ));; *) echo "$1";; esac; }

# check NAME SPLIT FRAMES: tiles of examples/NAME.npr against the whole
# render(s) already in $OUT/NAME.whole*.png
check() {
  name=$1; split=$2; frames=$3; n=$(split_count "$split"); tag=$(echo "$split" | tr x _)
  rm -f "$OUT/$name.$tag".*
  i=1; ok=1
  while [ "$i" -le "$n" ]; do
    if [ -n "$frames" ]; then
      "$SUMI" render "$ROOT/examples/$name.npr" --frames "$frames" --tile "$i/$split" --quiet \
        -o "$OUT/$name.$tag.####.t$i.png" >"$OUT/$name.$tag.log" 2>&1 || ok=0
    else
      "$SUMI" render "$ROOT/examples/$name.npr" --tile "$i/$split" -o "$OUT/$name.$tag.t$i.png" \
        >"$OUT/$name.$tag.log" 2>&1 || ok=0
    fi
    [ "$ok" = 1 ] || { echo "FAIL tiles/$name $split (tile $i did not render)"; sed 's/^/  /' "$OUT/$name.$tag.log" | head -5; failed=$((failed + 1)); return; }
    i=$((i + 1))
  done
  for whole in "$OUT/$name".whole*.png; do
    fr=$(basename "$whole" .png | sed -n 's/.*whole\.\{0,1\}//p')   # the frame number, or empty
    tiles=$(ls "$OUT/$name.$tag".${fr:+$fr.}t*.png)
    # shellcheck disable=SC2086
    if "$SUMI" assemble $tiles -o "$OUT/$name.$tag.${fr:+$fr.}png" >"$OUT/$name.$tag.log" 2>&1 &&
       cmp -s "$whole" "$OUT/$name.$tag.${fr:+$fr.}png"; then
      passed=$((passed + 1))
    else
      failed=$((failed + 1))
      echo "FAIL tiles/$name $split${fr:+ frame $fr}: assembled tiles differ from the whole render"
      sed 's/^/  /' "$OUT/$name.$tag.log" | head -5
      echo "  whole: $whole  assembled: $OUT/$name.$tag.${fr:+$fr.}png"
    fi
  done
}

for f in "$ROOT"/examples/*.npr; do
  name=$(basename "$f" .npr)
  need=$(head -3 "$f" | sed -n 's|^// needs: *||p')
  frames=$(head -3 "$f" | sed -n 's|^// frames: *||p')
  if [ -n "$need" ] && [ ! -e "$need" ]; then skipped=$((skipped + 1)); echo "skip tiles/$name ($need is not installed)"; continue; fi
  rm -f "$OUT/$name".whole*.png
  if [ -n "$frames" ]; then
    "$SUMI" render "$f" --frames "$frames" --quiet -o "$OUT/$name.whole.####.png" >"$OUT/$name.log" 2>&1
  else
    "$SUMI" render "$f" -o "$OUT/$name.whole.png" >"$OUT/$name.log" 2>&1
  fi || { failed=$((failed + 1)); echo "FAIL tiles/$name (the whole render failed)"; sed 's/^/  /' "$OUT/$name.log" | head -5; continue; }
  check "$name" 3 "$frames"
  check "$name" 2x3 "$frames"
done

if [ "$skipped" -gt 0 ]; then echo "$passed passed, $failed failed, $skipped skipped"
else echo "$passed passed, $failed failed"; fi
