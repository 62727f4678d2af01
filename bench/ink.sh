#!/bin/sh
# make bench, Chinese ink interiors (issue 19): Wuson from Debian's
# assimp-testmodels filling most of a 1920x1080 frame, on one thread.
#   bench/ink_wuson.npr     the interior alone: Gouraud (raster and the tile
#                           pass), quantise, diffusion at medium, box filter,
#                           the composite onto a white sheet
#   bench/ink_painting.npr  the whole painting: the same on the xuan sheet,
#                           under brush strokes along the silhouettes
# Each runs RUNS times (default 7); for every --stats stage the median is
# printed, then the frame (prepare through the last stage drawn: no
# parsing, no PNG encoding) and the ink stages alone (quantise, diffuse,
# box, canvas). Ink quantise runs inside raster+shade (the canvas takes
# each tile's samples as the tile pass draws them): its time is the
# workers' CPU time, not added to the frame again. Aims: the interior
# under 15 ms, the painting under 40 ms.
# Skipped when assimp-testmodels is not installed. Wall times on a shared
# machine are noisy: CALLGRIND=1 adds, per scene, one run under callgrind
# (one thread) and each stage's instructions, the inclusive cost of its
# function (render_prepare, render_frame: the tile pass, with canvas_tile:
# the quantise inside it, paper_create, ink_diffuse, ink_box_filter_rect,
# the rest of canvas_finish: the composite, line_render_frame), and the
# frame's (render_scene).
#
#   sh bench/ink.sh [path/to/sumi]
set -e
SUMI=${1:-build/sumi}
RUNS=${RUNS:-7}
DIR=build/bench
MODEL=/usr/share/assimp/models/OBJ/WusonOBJ.obj
mkdir -p "$DIR"
if [ ! -f "$MODEL" ]; then echo "ink bench skipped ($MODEL is not installed: assimp-testmodels)"; exit 0; fi

median() { sort -n | awk '{ v[NR] = $1 } END { if (NR == 0) print "-"; else if (NR % 2) print v[(NR + 1) / 2]; else printf "%.2f\n", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

# run SCENE TAG: RUNS renders at 1920x1080, one thread, stats into $DIR/ink_TAG_i.txt
run() {
  rm -f "$DIR"/ink_"$2"_*.txt   # an earlier invocation's runs, maybe more of them
  i=1
  while [ "$i" -le "$RUNS" ]; do
    "$SUMI" render "$1" -o "$DIR/ink_$2.png" --threads 1 --stats 2>"$DIR/ink_$2_$i.txt" >/dev/null
    i=$((i + 1))
  done
}

# the sum of the stages whose names match the awk pattern, per run, then its median
sum_of() {
  for f in "$DIR"/ink_"$1"_*.txt; do
    awk -v pat="$2" '/^stats: / {
        sub(/^stats: /, ""); ms = 0; name = "";
        for (i = 1; i <= NF; i++) if ($(i + 1) == "ms") { ms = $i; break } else name = name (name ? " " : "") $i;
        if ($(i + 2) == "cpu") next;   # worker CPU time, not wall
        if (name ~ pat) t += ms;
      } END { printf "%.2f\n", t }' "$f"
  done | median
}

report() {
  stages=$(sed -n 's/^stats: \(.*[a-z+]\) \{1,\}[0-9.]\{1,\} ms.*/\1/p' "$DIR/ink_$1_1.txt" | grep -v -e '^peak' -e '^parse' -e '^eval' -e '^write' -e '^image library')
  echo "$stages" | while read -r st; do
    [ -n "$st" ] || continue
    m=$(for f in "$DIR"/ink_"$1"_*.txt; do
          grep "^stats: $st  *[0-9]" "$f" | head -1 | sed 's/^stats: [^0-9]*\([0-9.]*\) ms.*/\1/'
        done | median)
    printf '  %-18s %8s ms\n' "$st" "$m"
  done
  printf '  %-18s %8s ms\n' "= ink stages" "$(sum_of "$1" '^(ink |canvas|paper)')"
  printf '  %-18s %8s ms   (aim %s)\n' "= frame" \
    "$(sum_of "$1" '^(prepare|tessellate|setup|raster\+shade|ink |canvas|paper|lines )')" "$2"
}

run bench/ink_wuson.npr interior
echo "ink interior, Wuson 1920x1080, 1 thread, median of $RUNS:"
report interior "15 ms"
run bench/ink_painting.npr painting
echo "ink painting (interior, xuan sheet, brush strokes), Wuson 1920x1080, 1 thread, median of $RUNS:"
report painting "40 ms"

[ -n "${CALLGRIND:-}" ] || exit 0
for tag in interior painting; do
  npr=bench/ink_wuson.npr; [ "$tag" = painting ] && npr=bench/ink_painting.npr
  out="$DIR/ink_$tag.callgrind"
  valgrind --tool=callgrind --callgrind-out-file="$out" \
    "$SUMI" render "$npr" -o "$DIR/ink_$tag.cg.png" --threads 1 --quiet >/dev/null 2>"$DIR/ink_$tag.callgrind.log"
  echo "ink $tag, instructions (callgrind, one thread):"
  callgrind_annotate --inclusive=yes "$out" 2>/dev/null | python3 -c '
import re, sys
want = {"render_prepare": "prepare", "render_frame": "tile pass", "canvas_tile": "ink quantise",
        "paper_create": "paper", "ink_diffuse": "ink diffuse", "ink_box_filter_rect": "ink box",
        "canvas_finish": "canvas", "line_render_frame": "lines", "render_scene": "frame"}
got = {}
for line in sys.stdin:
    m = re.match(r"\s*([\d,]+)\s+\([^)]*\)\s+(\S+):(\S+)", line)
    if not m: continue
    fn = m.group(3).split("'"'"'")[0]
    if fn in want and want[fn] not in got: got[want[fn]] = int(m.group(1).replace(",", ""))
got["canvas"] = got.get("canvas", 0) - sum(got.get(k, 0) for k in ("ink diffuse", "ink box"))
names = {"canvas": "composite", "ink quantise": "  of it quantise"}
for k in ["prepare", "tile pass", "ink quantise", "paper", "ink diffuse", "ink box", "canvas", "lines", "frame"]:
    if k in got: print("  %-18s %8.1f M" % (names.get(k, k), got[k] / 1e6))
'
done
