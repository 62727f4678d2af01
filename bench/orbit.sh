#!/bin/sh
# make bench-orbit: an animation of a static mesh (issue 24, item 3).
# bench/bigmesh_wuson_orbit.npr (Wuson from assimp-testmodels subdivided
# to level 4, toon with silhouettes and creases at 1920x1080) rendered as
# FRAMES frames of a camera orbit in one `sumi render --frames` run on one
# thread. --stats adds up over a run's frames, so each stage's cost per
# frame after the first is (its total at the last frame - its total at the
# first) / (FRAMES - 1); the first frame's figures and the per-frame
# figures are printed side by side, with the frame cost (setup +
# raster+shade + every lines stage + write), the whole run's wall and CPU
# time and peak RSS. Median over RUNS runs.
#
#   sh bench/orbit.sh [path/to/sumi]      RUNS=3 FRAMES=5
set -e
SUMI=${1:-build/sumi}
RUNS=${RUNS:-3}
FRAMES=${FRAMES:-5}
NPR=bench/bigmesh_wuson_orbit.npr
DIR=build/bench/orbit
mkdir -p "$DIR"
mesh=$(sed -n 's/.*mesh("\([^"]*\)").*/\1/p' "$NPR" | head -1)
[ -f "$mesh" ] || { echo "orbit: $mesh missing (assimp-testmodels): skipped"; exit 0; }
command -v python3 >/dev/null || { echo "bench-orbit: needs python3"; exit 1; }
last=$((FRAMES - 1))
i=1
while [ "$i" -le "$RUNS" ]; do
  /usr/bin/time -f "%e %M %U %S" -o "$DIR/run.$i.time" \
    "$SUMI" render "$NPR" --frames "0:$last" --threads 1 --stats --quiet -o "$DIR/orbit_####.png" 2>"$DIR/run.$i.stats"
  i=$((i + 1))
done
python3 - "$FRAMES" "$DIR" "$RUNS" <<'PY'
import re, statistics, sys
frames, d, runs = int(sys.argv[1]), sys.argv[2], int(sys.argv[3])
stats = ["%s/run.%d.stats" % (d, i) for i in range(1, runs + 1)]
STAGES = ["eval", "subdiv", "tessellate", "prepare", "setup", "raster+shade", "lines edges",
          "lines reference", "lines trace", "lines link", "lines strokes", "lines draw", "write"]
PERFRAME = STAGES[4:]
first, later = {s: [] for s in STAGES}, {s: [] for s in STAGES}
for path in stats:
    blocks, cur = [], {}
    for line in open(path):
        m = re.match(r"stats: (.+?)\s+([\d.]+) ms", line)
        if m: cur[m.group(1)] = float(m.group(2))
        if line.startswith("stats: peak RSS"): blocks.append(cur); cur = {}
    if len(blocks) != frames: sys.exit("orbit: %s has %d frames of stats, not %d" % (path, len(blocks), frames))
    for s in STAGES:
        a, b = blocks[0].get(s, 0.0), blocks[-1].get(s, 0.0)
        first[s].append(a)
        later[s].append((b - a) / (frames - 1))
print("orbit (%s frames of Wuson L4, 1.43 M triangles, 1920x1080, 1 thread), medians of %d runs:" % (frames, runs))
print("  %-18s %12s %12s" % ("stage", "frame 0", "later frames"))
for s in STAGES:
    print("  %-18s %9.1f ms %9.1f ms" % (s, statistics.median(first[s]), statistics.median(later[s])))
f0 = sum(statistics.median(first[s]) for s in PERFRAME)
fl = sum(statistics.median(later[s]) for s in PERFRAME)
pre = sum(statistics.median(later[s]) for s in STAGES[:4])
print("  %-18s %9.1f ms %9.1f ms   (setup + raster+shade + lines + write; aim < 60)" % ("frame cost", f0, fl))
print("  %-18s %12s %9.1f ms   (eval + subdiv + tessellate + prepare a later frame)" % ("scene again", "", pre))
t = [open("%s/run.%d.time" % (d, i)).read().split() for i in range(1, runs + 1)]
wall = statistics.median(float(x[0]) for x in t)
cpu = statistics.median(float(x[2]) + float(x[3]) for x in t)
rss = statistics.median(float(x[1]) for x in t)
print("  whole run: wall %.2f s, CPU %.2f s (%.2f s a frame), peak RSS %.0f MiB" % (wall, cpu, cpu / frames, rss / 1024))
PY
