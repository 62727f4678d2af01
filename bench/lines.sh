#!/bin/sh
# make bench, line stage: the toon teapot with ribbon lines
# (bench/lines_teapot.npr, ~25,000 triangles) at 1280x720 and 1920x1080
# on one thread, and a scene whose lines have nothing in view
# (bench/lines_empty.npr) at 1920x1080.
#
#   sh bench/lines.sh [path/to/sumi]
#
# Each configuration runs RUNS times (default 7); for every --stats stage
# the median over the runs is printed, then the frame (prepare through the
# last line stage: fill and lines, no parsing, no PNG encoding) and the
# line stages alone. The paper's figures (Core i5 + GPU, §3.2): all scenes
# > 30 fps at 720p; its analysis alone caps an empty 1080p scene at ~30 fps.
# Aim: frame < 33 ms at 1080p on one core; the empty scene's lines ~0 ms.
#
# If `blender` is installed and the peer script is in $SUMI_SHARED (default
# ../shared), the same teapot is rendered with Freestyle lines at
# 1920x1080 (Cycles, 1 thread, as ../shared/peers/run_blender.sh does) and
# the whole-process wall-time ratio is printed; otherwise that is skipped.
set -e
SUMI=${1:-build/sumi}
SHARED=${SUMI_SHARED:-../shared}
RUNS=${RUNS:-7}
DIR=build/bench
mkdir -p "$DIR"

# median of the numbers on standard input
median() { sort -n | awk '{ v[NR] = $1 } END { if (NR == 0) print "-"; else if (NR % 2) print v[(NR + 1) / 2]; else printf "%.2f\n", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

# run SCENE W H: RUNS renders, stats into $DIR/lines_W_H_i.txt
run() {
  i=1
  while [ "$i" -le "$RUNS" ]; do
    "$SUMI" render "$1" -o "$DIR/lines.png" -W "$2" -H "$3" --threads 1 --stats 2>"$DIR/lines_$4_$i.txt" >/dev/null
    i=$((i + 1))
  done
}

# report TAG: per-stage medians, frame and lines totals
report() {
  stages=$(sed -n 's/^stats: \(.*[a-z+]\) \{1,\}[0-9.]\{1,\} ms.*/\1/p' "$DIR/lines_$1_1.txt" | grep -v '^peak')
  echo "$stages" | while read -r st; do
    [ -n "$st" ] || continue
    m=$(for f in "$DIR"/lines_"$1"_*.txt; do
          grep "^stats: $st  *[0-9]" "$f" | head -1 | sed 's/^stats: [^0-9]*\([0-9.]*\) ms.*/\1/'
        done | median)
    extra=$(grep "^stats: $st  *[0-9]" "$DIR/lines_$1_1.txt" | head -1 | sed -n 's/.* ms *\(cpu\)\{0,1\} *\([a-z].*\)/\2/p')
    printf '  %-18s %8s ms  %s\n' "$st" "$m" "$extra"
  done
  for what in frame lines; do
    m=$(for f in "$DIR"/lines_"$1"_*.txt; do
          awk -v what="$what" '/^stats: / {
              sub(/^stats: /, ""); ms = 0; name = "";
              for (i = 1; i <= NF; i++) if ($(i + 1) == "ms") { ms = $i; break } else name = name (name ? " " : "") $i;
              if ($(i + 2) == "cpu") next;   # worker CPU time, not wall
              if (what == "lines" && name ~ /^lines /) t += ms;
              if (what == "frame" && (name ~ /^lines / || name == "prepare" || name == "tessellate" ||
                                      name == "setup" || name == "raster+shade")) t += ms;
            } END { printf "%.2f\n", t }' "$f"
        done | median)
    printf '  %-18s %8s ms\n' "= $what" "$m"
  done
}

for size in 1280x720 1920x1080; do
  W=${size%x*}; H=${size#*x}
  run bench/lines_teapot.npr "$W" "$H" "teapot_$size"
  echo "lines teapot $size, 1 thread, median of $RUNS:"
  report "teapot_$size"
done
run bench/lines_empty.npr 1920 1080 empty
echo "lines empty scene 1920x1080, 1 thread, median of $RUNS:"
report empty

if command -v blender >/dev/null && [ -f "$SHARED/peers/blender_teapot.py" ] && [ -f "$SHARED/data/teapot.txt" ]; then
  t0=$(date +%s.%N)
  "$SUMI" render bench/lines_teapot.npr -o "$DIR/lines_1080.png" -W 1920 -H 1080 --threads 1 >/dev/null 2>&1
  t1=$(date +%s.%N)
  blender -b --factory-startup --python-exit-code 1 -t 1 -P "$SHARED/peers/blender_teapot.py" -- \
    "$SHARED/data/teapot.txt" "$DIR/blender_freestyle_1080.png" 1920 1080 16 16 1 >"$DIR/blender.log" 2>&1
  t2=$(date +%s.%N)
  awk -v a="$t0" -v b="$t1" -v c="$t2" 'BEGIN {
    printf "Freestyle (Blender, Cycles 16 spp, 1 thread) 1920x1080: %.2f s; sumi %.2f s; ratio %.1fx\n", c - b, b - a, (c - b) / (b - a) }'
else
  echo "Freestyle comparison skipped (needs blender and \$SUMI_SHARED/peers/blender_teapot.py)"
fi
