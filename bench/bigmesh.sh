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
# function: subdiv_mesh, render_pass_begin or the pass_begin it wraps, render_pass_run less
# hand_bands, line_edges_build, line_ref_build, the rest of line_render,
# hand_bands or else image_write_opts), which a
# shared machine does not disturb. The scenes need assimp-testmodels
# (make deps installs it for this target); a scene whose file is absent
# is skipped.
#
# Peers, in the same run, one thread each, on the triangles sumi renders
# (`sumi export` of the scene, welded) with sumi's camera, light and image
# size (from `sumi eval --scene`), medians of PEER_RUNS runs:
#   POV-Ray  the mesh as one mesh2 (bench/stl_to_pov.py, written once and
#            kept while the mesh is the same), smooth shaded, a parallel
#            light, no shadows; no lines (POV-Ray draws none). Its parse
#            and trace CPU (its own statistics) and the whole process.
#   Blender  Cycles on the CPU, 1 sample, direct light only, a toon BSDF,
#            Freestyle silhouettes and creases (bench/bigmesh_blender.py);
#            skipped when blender is not installed. Its mesh building and
#            render (Cycles + Freestyle) CPU, and the whole process.
# Each peer's image is checked against sumi's: the share of pixels that
# are background in one and not the other (silhouette agreement, 1 =
# the same outline). Ratios are the peer's over sumi's: whole process CPU,
# and the peer's render (POV-Ray trace, Blender render) over sumi's per
# frame. PEERS=0 leaves the peers out; PEERS=only runs them without sumi's
# 2-thread runs and callgrind (sumi's 1-thread runs give the ratios).
#
#   sh bench/bigmesh.sh [path/to/sumi]      RUNS=5 PEER_RUNS=3 PEERS=1 SCENES="wuson duck engine torus"
#                                           POVRAY=povray BLENDER=blender (none: leave it out)
set -e
SUMI=${1:-build/sumi}
RUNS=${RUNS:-5}
SCENES=${SCENES:-wuson duck engine torus}
PEERS=${PEERS:-1}
PEER_RUNS=${PEER_RUNS:-3}
POVRAY=${POVRAY:-povray}     # POVRAY=none or BLENDER=none leaves that peer out
BLENDER=${BLENDER:-blender}
DIR=build/bench/bigmesh
mkdir -p "$DIR"
command -v python3 >/dev/null || { echo "bench-bigmesh: needs python3"; exit 1; }

# The peers' converters want numpy and PIL (python3-numpy, python3-pil):
# Debian's python3 has them where another python3 on PATH may not.
PY=python3
"$PY" -c 'import numpy, PIL' 2>/dev/null || PY=/usr/bin/python3
pov="" blender=""
if [ "$PEERS" != 0 ]; then
  if ! "$PY" -c 'import numpy, PIL' 2>/dev/null; then echo "bench-bigmesh: no python3 with numpy and PIL: peers skipped"
  else
    if command -v "$POVRAY" >/dev/null; then pov=1; else echo "bench-bigmesh: povray not installed: POV-Ray skipped"; fi
    if command -v "$BLENDER" >/dev/null; then blender=1; else echo "bench-bigmesh: blender not installed: Blender skipped"; fi
  fi
fi

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

# cpu FILES...: user + sys seconds of each /usr/bin/time "%e %M %U %S" file
cpu() { for f in "$@"; do cut -d' ' -f3,4 "$f" | awk '{ print $1 + $2 }'; done | median; }
col() { n=$1; shift; for f in "$@"; do cut -d' ' -f"$n" "$f"; done | median; }

# povstat WHAT FILES...: the CPU seconds of POV-Ray's "Parse Time" or
# "Trace Time" in each of its logs
povstat() {
  what=$1; shift
  for f in "$@"; do
    awk -v w="$what" 'index($0, w) { hit = 1; next } hit && /CPU-seconds/ { for (i = 1; i <= NF; i++) if ($i == "with") print $(i + 1); exit }' "$f"
  done | median
}

# blstat KEY FILES...: KEY=value of the BENCH line of each Blender log
blstat() { key=$1; shift; for f in "$@"; do sed -n "s/^BENCH.* $key=\([0-9.]*\).*/\1/p" "$f"; done | median; }

ratio() { python3 -c 'import sys; a, b = float(sys.argv[1]), float(sys.argv[2]); print("%.1fx" % (a / b) if b > 0 else "-")' "$1" "$2"; }

# peers SCENE NPR PER_FRAME_MS SUMI_CPU_S SUMI_RSS_KB: the same scene in
# POV-Ray and Blender, and how their images' outlines agree with sumi's
peers() {
  s=$1 npr=$2 frame=$(python3 -c "print($3 / 1000)") scpu=$4 srss=$5
  "$SUMI" eval "$npr" --scene >"$DIR/$s.scene.txt" 2>/dev/null
  "$SUMI" export "$npr" -o "$DIR/$s.new.stl" 2>/dev/null
  if cmp -s "$DIR/$s.new.stl" "$DIR/$s.stl"; then rm "$DIR/$s.new.stl"; else mv "$DIR/$s.new.stl" "$DIR/$s.stl"; fi
  set -- $(sed -n 's/^output.size //p' "$DIR/$s.scene.txt"); W=$1 H=$2
  smooth=""   # a subdivided surface shades smoothly; a polygon mesh keeps edges over 45 degrees
  grep -q 'geometry.subdiv' "$DIR/$s.scene.txt" || smooth="--smooth-angle 45"
  echo "  peers, 1 thread, medians of $PEER_RUNS runs (CPU is user + sys):"
  printf '    %-8s whole run CPU %6.2f s, peak %5.0f MiB; per frame %.3f s   (toon bands, silhouette and crease lines)\n' \
    sumi "$scpu" "$(python3 -c "print($srss / 1024)")" "$frame"
  if [ -n "$pov" ]; then
    if [ ! -f "$DIR/$s.pov" ] || [ "$DIR/$s.stl" -nt "$DIR/$s.pov" ] || ! cmp -s "$DIR/$s.scene.txt" "$DIR/$s.pov.scene.txt"; then
      "$PY" bench/stl_to_pov.py "$DIR/$s.scene.txt" "$DIR/$s.stl" "$DIR/$s.pov" $smooth
      cp "$DIR/$s.scene.txt" "$DIR/$s.pov.scene.txt"
    fi
    i=1
    rm -f "$DIR/$s.pov."[0-9]*.time "$DIR/$s.pov."[0-9]*.log
    while [ "$i" -le "$PEER_RUNS" ]; do
      /usr/bin/time -f "%e %M %U %S" -o "$DIR/$s.pov.$i.time" \
        "$POVRAY" +I"$DIR/$s.pov" +O"$DIR/$s.pov.png" +FN +W"$W" +H"$H" -D -A +WT1 -V >/dev/null 2>"$DIR/$s.pov.$i.log" \
        || { echo "    POV-Ray failed: $DIR/$s.pov.$i.log"; return; }
      i=$((i + 1))
    done
    pcpu=$(cpu "$DIR/$s.pov."*.time) prss=$(col 2 "$DIR/$s.pov."*.time)
    parse=$(povstat "Parse Time" "$DIR/$s.pov."*.log) trace=$(povstat "Trace Time" "$DIR/$s.pov."*.log)
    agree=$("$PY" bench/outline_agree.py "$DIR/$s.t1.png" "$DIR/$s.pov.png")
    printf '    %-8s whole run CPU %6.2f s, peak %5.0f MiB; parse %.2f s, trace %.2f s   (smooth-shaded mesh2, same camera and light, no lines); outline agreement %s\n' \
      POV-Ray "$pcpu" "$(python3 -c "print($prss / 1024)")" "$parse" "$trace" "$agree"
    echo "             POV-Ray over sumi: whole run CPU $(ratio "$pcpu" "$scpu"), trace over sumi's per frame $(ratio "$trace" "$frame"), peak memory $(ratio "$prss" "$srss")"
  fi
  if [ -n "$blender" ]; then
    i=1
    rm -f "$DIR/$s.blender."[0-9]*.time "$DIR/$s.blender."[0-9]*.log
    while [ "$i" -le "$PEER_RUNS" ]; do
      /usr/bin/time -f "%e %M %U %S" -o "$DIR/$s.blender.$i.time" \
        "$BLENDER" -b --factory-startup --python-exit-code 1 -t 1 -P bench/bigmesh_blender.py -- \
          "$DIR/$s.scene.txt" "$DIR/$s.stl" "$DIR/$s.blender.png" $smooth >"$DIR/$s.blender.$i.log" 2>&1 \
        || { echo "    Blender failed: $DIR/$s.blender.$i.log"; return; }
      i=$((i + 1))
    done
    bcpu=$(cpu "$DIR/$s.blender."*.time) brss=$(col 2 "$DIR/$s.blender."*.time)
    bimp=$(blstat import_cpu "$DIR/$s.blender."*.log) brend=$(blstat render_cpu "$DIR/$s.blender."*.log)
    agree=$("$PY" bench/outline_agree.py "$DIR/$s.t1.png" "$DIR/$s.blender.png")
    printf '    %-8s whole run CPU %6.2f s, peak %5.0f MiB; mesh %.2f s, render %.2f s   (Cycles CPU 1 sample, toon BSDF, Freestyle silhouettes and creases); outline agreement %s\n' \
      Blender "$bcpu" "$(python3 -c "print($brss / 1024)")" "$bimp" "$brend" "$agree"
    echo "             Blender over sumi: whole run CPU $(ratio "$bcpu" "$scpu"), render over sumi's per frame $(ratio "$brend" "$frame"), peak memory $(ratio "$brss" "$srss")"
  fi
}

for s in $SCENES; do
  npr=$(scene_file "$s")
  mesh=$(sed -n 's/.*mesh("\([^"]*\)").*/\1/p' "$npr" | head -1)
  if [ -n "$mesh" ] && [ ! -f "$mesh" ]; then echo "$s: $mesh missing (assimp-testmodels): skipped"; continue; fi
  "$SUMI" render "$npr" -o "$DIR/$s.png" --threads 1 --quiet   # warm up; must succeed
  threads="1 2"; [ "$PEERS" = only ] && threads=1
  rm -f "$DIR/$s.t"[12].*.time "$DIR/$s.t"[12].*.stats   # an earlier run's extra RUNS must not join the medians
  for t in $threads; do
    i=1
    while [ "$i" -le "$RUNS" ]; do
      /usr/bin/time -f "%e %M %U %S" -o "$DIR/$s.t$t.$i.time" \
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
  c1=$(for f in "$DIR/$s.t1."*.time; do cut -d' ' -f3,4 "$f" | awk '{ print $1 + $2 }'; done | median)
  if [ "$PEERS" = only ]; then
    printf '  peak RSS %.0f MiB (aim < 300); whole run wall %.2f s, CPU %.2f s on 1 thread\n' \
      "$(python3 -c "print($rss / 1024)")" "$w1" "$c1"
  else
    w2=$(for f in "$DIR/$s.t2."*.time; do cut -d' ' -f1 "$f"; done | median)
    printf '  peak RSS %.0f MiB (aim < 300); whole run wall %.2f s (CPU %.2f s) on 1 thread, %.2f s on 2 (%.2fx)\n' \
      "$(python3 -c "print($rss / 1024)")" "$w1" "$c1" "$w2" "$(python3 -c "print($w1 / $w2 if $w2 > 0 else 0)")"
  fi
  [ -n "$pov$blender" ] && peers "$s" "$npr" "$sum" "$c1" "$rss"
  if [ -n "${CALLGRIND:-}" ] && [ "$PEERS" != only ]; then
    out="$DIR/$s.callgrind"
    valgrind --tool=callgrind --callgrind-out-file="$out" \
      "$SUMI" render "$npr" -o "$DIR/$s.cg.png" --threads 1 --quiet >/dev/null 2>"$DIR/$s.callgrind.log"
    callgrind_annotate --inclusive=yes "$out" 2>/dev/null | python3 -c '
import re, sys
want = {"subdiv_mesh": "subdiv", "render_pass_begin": "setup", "pass_begin": "setup", "render_pass_run": "pass",
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
