#!/bin/sh
# make bench, threshold textures (issue 15): the bench teapot at 1920x1080
# on one thread cross-hatched (bench/teapot_hatch.npr: two hatch layers over
# the patches' (u, v), filtered) against the same teapot in shade toon
# (bench/teapot_toon.npr), in the same run (bench/threshold_work.py: each
# scene's work is its frame less the same command at 1x1, the four runs of
# a round alternating). The aim: at most 1.5x the toon frame's work. The
# second ratio takes the frames' PNG encoding off (a hatched image is far
# busier for zlib than a banded one).
# CALLGRIND=1 also counts the instructions of the four runs under
# valgrind's callgrind (repeatable on a shared machine, where times are
# not; a few minutes) and gives the ratio of the two scenes' work.
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
if [ -n "${CALLGRIND:-}" ]; then
  ir() {   # SCENE W H: the run's instruction count
    valgrind --tool=callgrind --callgrind-out-file=/dev/null "$SUMI" render "$1" -o build/bench/work.png \
      -W "$2" -H "$3" --threads 1 --quiet 2>&1 | sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
  }
  ha=$(ir bench/teapot_hatch.npr 1920 1080); h1=$(ir bench/teapot_hatch.npr 1 1)
  ta=$(ir bench/teapot_toon.npr 1920 1080); t1=$(ir bench/teapot_toon.npr 1 1)
  awk -v ha="$ha" -v h1="$h1" -v ta="$ta" -v t1="$t1" 'BEGIN {
    printf "  instructions (callgrind), frame less its 1x1 run: cross-hatched %.1fM, toon %.1fM: %.2fx (aim: at most 1.5x)\n",
           (ha - h1) / 1e6, (ta - t1) / 1e6, (ha - h1) / (ta - t1) }'
fi
