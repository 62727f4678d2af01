#!/bin/sh
# make bench, CLAHE (issue 15): sumi's CLAHE (src/render/clahe.c) against
# OpenCV's cv2.createCLAHE (Debian's python3-opencv, run with /usr/bin/python3,
# one thread each) on the same 1024 x 1024 photograph (four of skimage's,
# python3-skimage), with the same tile grid and clip limit: the largest
# difference at any pixel (aim: 2 grey levels) and the time ratio (aim: at
# most 1.5x OpenCV's). Then a threshold texture's whole mip pyramid (CLAHE
# and ranking at every level, src/render/texture.c) against one level of
# it at the same window (aim: at most 2x). Each run is the median of 21 in
# process; ROUNDS (5) runs of sumi and OpenCV alternate; the medians of the
# rounds, and of the ratios within a round, are printed.
# Skipped without python3-opencv or python3-skimage.
#   sh bench/clahe.sh [BUILD_DIR]
set -e
BUILD=${1:-build}
DIR=build/bench
PY=/usr/bin/python3
DATA=/usr/lib/python3/dist-packages/skimage/data
mkdir -p "$DIR"
if [ ! -f "$DATA/brick.png" ] || ! "$PY" -c "import cv2, numpy" 2>/dev/null; then
  echo "bench-clahe: python3-opencv or python3-skimage missing, skipped"
  exit 0
fi
OBJS=$(find "$BUILD/src" -name '*.o' ! -name main.o)
cc -std=c11 -D_DEFAULT_SOURCE -O2 -o "$DIR/clahe_bench" bench/clahe_bench.c $OBJS \
   $(sed -n '/^LDLIBS *:=/{:a;/\\$/{N;s/\\\n//;ba};s/^LDLIBS *:= *//p}' Makefile)   # its continued lines joined
"$PY" bench/clahe_mosaic.py "$DATA" "$DIR/clahe_in.png"
ROUNDS=${ROUNDS:-5}
echo "CLAHE, 1024x1024 (skimage brick, grass, gravel, camera), 1 thread, medians of $ROUNDS alternating rounds:"
printf '  %-22s %9s %9s %7s %9s | %9s %9s %7s\n' "tiles, clip" "sumi ms" "opencv ms" "ratio" "max diff" "level ms" "pyramid" "ratio"
for cfg in "64 64 4" "64 64 0" "16 16 2" "8 8 40"; do
  set -- $cfg
  : >"$DIR/clahe_rounds.txt"
  r=0
  while [ "$r" -lt "$ROUNDS" ]; do   # sumi and OpenCV in turn, so a busy spell falls on both
    s=$("$DIR/clahe_bench" "$DIR/clahe_in.png" $1 $2 $3 "$DIR/clahe_sumi.raw")
    o=$("$PY" bench/clahe_opencv.py "$DIR/clahe_in.png" $1 $2 $3 "$DIR/clahe_sumi.raw")
    echo "$s $o" >>"$DIR/clahe_rounds.txt"
    r=$((r + 1))
  done
  "$PY" - "$DIR/clahe_rounds.txt" "$1x$2, clip $3" <<'PY'
import statistics, sys
rows = [list(map(float, l.split())) for l in open(sys.argv[1]) if l.strip()]
s, l, p, o, d = ([r[i] for r in rows] for i in range(5))
med = statistics.median
print("  %-22s %9.2f %9.2f %6.2fx %9d | %9.2f %9.2f %6.2fx" % (
    sys.argv[2], med(s), med(o), med([a / b for a, b in zip(s, o)]), max(d), med(l), med(p),
    med([b / a for a, b in zip(l, p)])))
PY
done
echo "  (aims: max diff <= 2 grey levels, sumi <= 1.5x OpenCV; pyramid <= 2x one level)"
