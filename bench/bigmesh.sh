#!/bin/sh
# make bench-bigmesh: large real meshes (issue 24). Four scenes at
# 1920x1080, toon with lines { kinds silhouette, crease(...); }:
#   wuson   assimp-testmodels OBJ/WusonOBJ.obj, subdivided to level 4 (1.43 M triangles)
#   duck    assimp-testmodels Collada/duck.dae, subdivided to level 4 (1.09 M triangles)
#   engine  assimp-testmodels glTF2 2CylinderEngine.glb as it is (110 k triangles)
#   torus   bench/subdiv.npr, a creased torus at level 5 (1.05 M triangles)
# For each: sumi's per-stage times from --stats (median over RUNS runs of
# each stage, ms; raster and shade are worker CPU, the rest wall) on one
# thread, the per-frame sum (setup + raster+shade + every lines stage +
# write), the median peak RSS, and the whole run's median wall time on 1
# and 2 threads. CALLGRIND=1 adds, per scene, one run under callgrind on
# one thread and each stage's instructions (inclusive cost of the stage's
# function: subdiv_mesh, render_pass_begin, render_pass_run less
# hand_bands, line_edges_build, line_ref_build, the rest of line_render,
# hand_bands or else image_write_opts), which a
# shared machine does not disturb. The scenes need assimp-testmodels
# (make deps installs it for this target); a scene whose file is absent
# is skipped.
#
#   sh bench/bigmesh.sh [path/to/sumi]      RUNS=5 SCENES="wuson duck engine torus"
set -e
SUMI=${1:-build/sumi}
RUNS=${RUNS:-5}
SCENES=${SCENES:-wuson duck engine torus}
DIR=build/bench/bigmesh
mkdir -p "$DIR"
command -v python3 >/dev/null || { echo "bench-bigmesh: needs python3"; exit 1; }

scene_file() { case $1 in torus) echo bench/subdiv.npr;; *) echo "bench/bigmesh_$1.npr";; esac; }

# the median of the numbers on standard input
median() { sort -g | awk '{ v[NR] = $1 } END { if (NR == 0) print "-"; else if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

# stage NAME FILES...: the stage's time (ms; a stage with a "cpu" figure
# only, its cpu) in each stats file
stage() {
  name=$1; shift
  for f in "$@"; do
    awk -v s="$name" '{ line = $0; sub(/^stats: /, "", line) }
      substr(line, 1, length(s)) == s && substr(line, length(s) + 1) ~ /^ +[0-9]/ {
        rest = substr(line, length(s) + 1); split(rest, w, " "); print w[1]; exit }' "$f"
  done | median
}

STAGES="subdiv|tessellate|setup|raster|shade|raster+shade|lines edges|lines reference|lines trace|lines link|lines strokes|lines draw|write"
PERFRAME="setup|raster+shade|lines edges|lines reference|lines trace|lines link|lines strokes|lines draw|write"

for s in $SCENES; do
  npr=$(scene_file "$s")
  mesh=$(sed -n 's/.*mesh("\([^"]*\)").*/\1/p' "$npr" | head -1)
  if [ -n "$mesh" ] && [ ! -f "$mesh" ]; then echo "$s: $mesh missing (assimp-testmodels): skipped"; continue; fi
  "$SUMI" render "$npr" -o "$DIR/$s.png" --threads 1 --quiet   # warm up; must succeed
  for t in 1 2; do
    i=1
    while [ "$i" -le "$RUNS" ]; do
      /usr/bin/time -f "%e %M" -o "$DIR/$s.t$t.$i.time" \
        "$SUMI" render "$npr" -o "$DIR/$s.t$t.png" --threads "$t" --stats --quiet 2>"$DIR/$s.t$t.$i.stats"
      i=$((i + 1))
    done
  done
  tris=$(grep '^stats: tessellate' "$DIR/$s.t1.1.stats" | sed 's/.*triangles //')
  echo "$s ($npr, $tris triangles), 1920x1080, 1 thread, medians of $RUNS runs:"
  sum=0
  IFS='|'
  for st in $STAGES; do
    v=$(stage "$st" "$DIR/$s.t1."*.stats)
    [ "$v" = "-" ] && continue
    printf '  %-18s %9.1f ms\n' "$st" "$v"
    case "|$PERFRAME|" in *"|$st|"*) sum=$(python3 -c "print($sum + $v)");; esac
  done
  unset IFS
  printf '  %-18s %9.1f ms   (setup + raster+shade + lines + write; aim < 60)\n' "per frame" "$sum"
  rss=$(for f in "$DIR/$s.t1."*.time; do cut -d' ' -f2 "$f"; done | median)
  w1=$(for f in "$DIR/$s.t1."*.time; do cut -d' ' -f1 "$f"; done | median)
  w2=$(for f in "$DIR/$s.t2."*.time; do cut -d' ' -f1 "$f"; done | median)
  printf '  peak RSS %.0f MiB (aim < 300); whole run wall %.2f s on 1 thread, %.2f s on 2 (%.2fx)\n' \
    "$(python3 -c "print($rss / 1024)")" "$w1" "$w2" "$(python3 -c "print($w1 / $w2 if $w2 > 0 else 0)")"
  if [ -n "${CALLGRIND:-}" ]; then
    out="$DIR/$s.callgrind"
    valgrind --tool=callgrind --callgrind-out-file="$out" \
      "$SUMI" render "$npr" -o "$DIR/$s.cg.png" --threads 1 --quiet >/dev/null 2>"$DIR/$s.callgrind.log"
    callgrind_annotate --inclusive=yes "$out" 2>/dev/null | python3 -c '
import re, sys
want = {"subdiv_mesh": "subdiv", "render_pass_begin": "setup", "render_pass_run": "pass",
        "line_edges_build": "lines edges", "line_ref_build": "lines reference", "line_render": "lines",
        "hand_bands": "bands", "image_write_opts": "write"}
got, total = {}, 0
for line in sys.stdin:
    m = re.match(r"\s*([\d,]+)\s+\([^)]*\)\s+(\S+):(\S+)", line)
    if not m:
        m2 = re.match(r"\s*([\d,]+)\s+\(100.0%\)\s+PROGRAM TOTALS", line) or re.match(r"\s*([\d,]+)\s+PROGRAM TOTALS", line)
        if m2: total = int(m2.group(1).replace(",", ""))
        continue
    fn = m.group(3).split("'"'"'")[0]
    if fn in want and want[fn] not in got: got[want[fn]] = int(m.group(1).replace(",", ""))
if "pass" in got: got["raster+shade"] = got.pop("pass") - got.get("bands", 0)
if "bands" in got: got["write"] = got.pop("bands")   # rows written inside the pass
if "lines" in got: got["lines rest"] = got.pop("lines") - got.get("lines edges", 0) - got.get("lines reference", 0)
order = ["subdiv", "setup", "raster+shade", "lines edges", "lines reference", "lines rest", "write"]
frame = sum(got.get(k, 0) for k in order[1:])
print("  instructions (callgrind, M): " + ", ".join("%s %d" % (k, got[k] / 1e6) for k in order if k in got)
      + ", per-frame %d, whole run %d" % (frame / 1e6, total / 1e6))
'
  fi
done
