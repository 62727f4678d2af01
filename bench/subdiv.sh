#!/bin/sh
# make bench (subdivision part): subdivide a torus to about 1 million
# triangles with OpenSubdiv and render it toon-shaded with lines at
# 1920x1080 on one thread. Prints sumi's per-stage times (--stats) for the
# median of 5 runs by wall time, and the peak memory.
# Aim: the render stages under 150 ms on one core, memory under 1 GB.
set -e
SUMI=${1:-build/sumi}
DIR=build/bench
mkdir -p "$DIR"
"$SUMI" render bench/subdiv.npr -o "$DIR/subdiv.png" --threads 1 --quiet   # warm up; must succeed
for i in 1 2 3 4 5; do
  /usr/bin/time -f "%e %M" -o "$DIR/subdiv.$i.time" \
    "$SUMI" render bench/subdiv.npr -o "$DIR/subdiv.png" --threads 1 --stats --quiet \
    2>"$DIR/subdiv.$i.stats"
done
median=$(for i in 1 2 3 4 5; do echo "$(cut -d' ' -f1 "$DIR/subdiv.$i.time") $i"; done |
         sort -n | sed -n 3p | cut -d' ' -f2)
echo "subdiv: torus 32x16 quads, level 5, 1920x1080, 1 thread; median run of 5:"
grep '^stats:' "$DIR/subdiv.$median.stats" | sed 's/^/  /'
# render stages: triangle setup, raster+shade (wall), and every lines stage
awk '/^stats: (setup|raster\+shade|lines )/ { for (i = 2; i <= NF; i++) if ($(i+1) == "ms") { t += $i; break } }
     END { printf "  render stages (setup + raster+shade + lines): %.1f ms\n", t }' "$DIR/subdiv.$median.stats"
read -r secs kb <"$DIR/subdiv.$median.time"
echo "  wall $(echo "$secs * 1000" | bc | cut -d. -f1) ms, peak RSS $((kb / 1024)) MiB (aim: render stages < 150 ms, memory < 1 GB)"
