#!/bin/sh
# make bench-parse: lex+parse throughput and peak memory on a generated
# 10 MB scene script. Reports the median of 5 runs; `sumi parse` does no
# evaluation and loads no image library, so this is the front end alone.
set -e
SUMI=${1:-build/sumi}
DIR=build/bench
mkdir -p "$DIR"
SRC="$DIR/parse_10mb.npr"
[ -f "$SRC" ] || python3 bench/gen_parse.py 10 >"$SRC"
BYTES=$(wc -c <"$SRC")
"$SUMI" parse "$SRC"   # warm the page cache; must be free of errors
times=""
for i in 1 2 3 4 5; do
  /usr/bin/time -f "%e %M" -o "$DIR/parse.time" "$SUMI" parse "$SRC"
  times="$times$(cat "$DIR/parse.time")\n"
done
printf "$times" | sort -n | sed -n 3p | while read -r secs kb; do
  python3 - "$BYTES" "$secs" "$kb" <<'PY'
import sys
size, secs, kb = int(sys.argv[1]), float(sys.argv[2]), int(sys.argv[3])
mb = size / 1e6
print(f"parse: {mb:.1f} MB source, median {secs*1000:.0f} ms over 5 runs -> {mb/max(secs,1e-9):.0f} MB/s")
print(f"parse: peak RSS {kb/1024:.1f} MiB = {kb*1024/size:.2f}x the source (aim: under 8x, at least 100 MB/s)")
PY
done
