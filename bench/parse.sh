#!/bin/sh
# make bench-parse: lex+parse throughput and peak memory on a generated
# 10 MB scene script. Reports medians of 5 runs: wall time, CPU time (user +
# sys, steadier than wall on a shared machine) and peak RSS. `sumi parse`
# does no evaluation and loads no image library, so this is the front end alone.
set -e
SUMI=${1:-build/sumi}
DIR=$(dirname "$SUMI")/bench   # beside the binary: each build dir has its own
mkdir -p "$DIR"
SRC="$DIR/parse_10mb.npr"
[ -f "$SRC" ] || python3 bench/gen_parse.py 10 >"$SRC"
"$SUMI" parse "$SRC"   # warm the page cache; must be free of errors
python3 - "$SUMI" "$SRC" <<'PY'
import os, statistics, sys, time
sumi, src = sys.argv[1], sys.argv[2]
size = os.path.getsize(src)
walls, cpus, rss = [], [], []
for _ in range(5):
    t0 = time.perf_counter()
    pid = os.spawnv(os.P_NOWAIT, sumi, [sumi, "parse", src])
    _, status, ru = os.wait4(pid, 0)   # this run's own usage, to the microsecond
    walls.append(time.perf_counter() - t0)
    if status != 0:
        sys.exit("parse: sumi failed")
    cpus.append(ru.ru_utime + ru.ru_stime)
    rss.append(ru.ru_maxrss * 1024)   # Linux reports kilobytes
mb = size / 1e6
wall, cpu, peak = statistics.median(walls), statistics.median(cpus), statistics.median(rss)
print(f"parse: {mb:.1f} MB source, median {wall*1000:.0f} ms over 5 runs -> {mb/max(wall,1e-9):.0f} MB/s"
      f" (CPU {cpu*1000:.0f} ms -> {mb/max(cpu,1e-9):.0f} MB/s)")
print(f"parse: peak RSS {peak/2**20:.1f} MiB = {peak/size:.2f}x the source (aim: under 8x, at least 100 MB/s)")
PY
