#!/bin/sh
# make bench, Chinese brush strokes (issue 18): Wuson from Debian's
# assimp-testmodels at 1920x1080 on one thread, its silhouettes culled by
# the endpoint test, chained within 2 px and painted with the default
# brush (bench/brush_wuson.npr), against the same edges drawn as ribbons as
# wide as the brush at its widest (bench/brush_wuson_ribbon.npr); the two
# runs alternate, so a busy spell of the shared machine falls on both.
#
#   sh bench/brush.sh [path/to/sumi]
#
# Prints, for each scene, the median (RUNS rounds, default 9) of every line
# stage of --stats and of the stroke stage (lines strokes + lines draw: the
# brush's path, dry brush and deposits, or the ribbons' ribs and ink), then
# the brush's stroke stage over the ribbons'. The thesis calls the brush
# its bottleneck ("a large overloading", ch. 4.5); the aim: the stroke
# stage under 10 ms on one core and under 2x the ribbons'. Skipped when
# assimp-testmodels is not installed.
set -e
SUMI=${1:-build/sumi}
RUNS=${RUNS:-9}
DIR=build/bench
MODEL=/usr/share/assimp/models/OFF/Wuson.off
mkdir -p "$DIR"
if [ ! -e "$MODEL" ]; then
  echo "brush strokes: skipped ($MODEL is not installed: apt-get install assimp-testmodels)"
  exit 0
fi

median() { sort -n | awk '{ v[NR] = $1 } END { if (NR == 0) print "-"; else if (NR % 2) print v[(NR + 1) / 2]; else printf "%.2f\n", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

# stage NAME FILE: its wall time in ms in one run's --stats
stage() { grep "^stats: $1  *[0-9]" "$2" | head -1 | sed 's/^stats: [^0-9]*\([0-9.]*\) ms.*/\1/'; }

i=1
while [ "$i" -le "$RUNS" ]; do
  for s in brush ribbon; do
    scene=bench/brush_wuson.npr
    [ "$s" = ribbon ] && scene=bench/brush_wuson_ribbon.npr
    "$SUMI" render "$scene" -o "$DIR/brush_$s.png" -W 1920 -H 1080 --threads 1 --stats 2>"$DIR/brush_${s}_$i.txt" >/dev/null
  done
  i=$((i + 1))
done

# report TAG: the median of each line stage, and of the stroke stage
report() {
  for st in "lines edges" "lines reference" "lines cull" "lines chain" "lines strokes" "lines draw"; do
    m=$(for f in "$DIR"/brush_"$1"_*.txt; do stage "$st" "$f"; done | median)
    extra=$(grep "^stats: $st  *[0-9]" "$DIR/brush_$1_1.txt" | head -1 | sed -n 's/.* ms *\([a-z].*\)/\1/p')
    printf '  %-18s %8s ms  %s\n' "$st" "$m" "$extra"
  done
  m=$(for f in "$DIR"/brush_"$1"_*.txt; do
        a=$(stage "lines strokes" "$f"); b=$(stage "lines draw" "$f")
        awk -v a="$a" -v b="$b" 'BEGIN { printf "%.3f\n", a + b }'
      done | median)
  printf '  %-18s %8s ms\n' "= stroke stage" "$m"
  eval "stroke_$1=$m"
}

echo "brush strokes, Wuson 1920x1080, 1 thread, median of $RUNS alternating runs:"
echo " brush (28 x 7 bristles, half-width up to 7 px, dry brush, turning):"
report brush
echo " ribbons on the same edges (14 px wide, procedural ink):"
report ribbon
awk -v a="$stroke_brush" -v b="$stroke_ribbon" 'BEGIN {
  printf "  brush stroke stage / ribbon stroke stage: %.2fx (aim: under 10 ms and under 2x)\n", a / b }'
