#!/bin/sh
# make bench, threshold textures (issue 15): the bench teapot at 1920x1080
# on one thread cross-hatched (bench/teapot_hatch.npr: two hatch layers over
# the patches' (u, v), filtered) against the same teapot in shade toon
# (bench/teapot_toon.npr), in the same run (bench/threshold_work.py: each
# scene's work is its frame less the same command at 1x1, the four runs of
# a round alternating). The aim: at most 1.5x the toon frame's work. The
# second ratio takes the frames' PNG encoding off (a hatched image is far
# busier for zlib than a banded one).
#   sh bench/threshold.sh [path/to/sumi]
set -e
SUMI=${1:-build/sumi}
RUNS=${RUNS:-9}
mkdir -p build/bench
command -v python3 >/dev/null || { echo "bench-threshold: needs python3, skipped"; exit 0; }
set -- $(python3 bench/threshold_work.py "$RUNS" "$SUMI" 1920 1080 bench/teapot_hatch.npr bench/teapot_toon.npr)
echo "threshold textures, teapot 1920x1080, 1 thread, medians of $RUNS rounds:"
printf '  %-36s %9s ms   less PNG encoding %9s ms\n' "cross-hatched (2 layers, filtered)" "$1" "$4"
printf '  %-36s %9s ms   less PNG encoding %9s ms\n' "toon" "$2" "$5"
printf '  hatched over toon: %sx (aim: at most 1.5x); less PNG encoding: %sx\n' "$3" "$6"
