#!/bin/sh
# The origami render stages at 512 x 512 (issue 7): the egg tessellation
# (157 faces, cyclic orders) and the crane, each mode timed end to end
# (face-ID buffer, shading, Sobel lines), median of 15 runs, against
# Mitani's reported times (Java, Core 2 Duo 2.6 GHz: 63 ms line, 93 ms
# illustration, 1515 ms shaded) and our aims (5, 5 and 20 ms).
# Needs the FOLD files of $SUMI_SHARED/data/fold (skipped when absent).
#   sh bench/origami.sh [BUILD_DIR]
set -e
BUILD=${1:-build}
SHARED=${SUMI_SHARED:-../shared}
DIR=build/bench
mkdir -p "$DIR"
[ -d "$SHARED/data/fold" ] || { echo "bench-origami: $SHARED/data/fold absent, skipped"; exit 0; }
OBJS=$(find "$BUILD/src" -name '*.o' ! -name main.o)
cc -std=c11 -D_DEFAULT_SOURCE -O2 -o "$DIR/origami_bench" bench/origami_bench.c $OBJS \
   -lcjson -losdCPU -lassimp -ldl -lm -pthread -lstdc++
for f in egg13-3_tessellation_state crane; do
  "$DIR/origami_bench" "$SHARED/data/fold/$f.fold" 512
done
echo "paper (Java, Core 2 Duo): line 63 ms, illustration 93 ms, shaded 1515 ms; aim: 5, 5, 20 ms"
