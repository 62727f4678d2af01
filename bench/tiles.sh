#!/bin/sh
# make bench, tiles: the lines scene (bench/lines_teapot.npr: toon fill,
# ribbon lines) at 7680x4320, rendered once whole and once as 8 tiles
# (8 rows of tiles) in their own processes, run 2 at a time as a
# scheduler would on this machine, then stitched by `sumi assemble`. Each
# process on one thread, under /usr/bin/time: its CPU time (user + system)
# and peak resident memory. The stitched frame must be the whole render's
# bytes.
#
#   sh bench/tiles.sh [path/to/sumi]
#
# Aims (issue 22): the tiles' summed CPU time within 1.15x the whole
# render's (the margins and what every tile repeats are the overhead),
# and each tile job's peak memory at most a quarter of the whole's.
# CALLGRIND=1 also counts each process's instructions under valgrind's
# callgrind (repeatable on a shared machine, where CPU time is not;
# minutes), and gives the ratio of those.
set -e
SUMI=${1:-build/sumi}
DIR=build/bench/tiles
SCENE=bench/lines_teapot.npr
W=${TILES_W:-7680}; H=${TILES_H:-4320}; N=8
rm -rf "$DIR"; mkdir -p "$DIR"
[ -x /usr/bin/time ] || { echo "bench tiles: needs /usr/bin/time (Debian's time)"; exit 1; }

# measure NAME CMD...: run CMD, keep "cpu_seconds peak_kib" in $DIR/NAME.time
# (and with CALLGRIND=1 its instruction count in $DIR/NAME.ir)
measure() {
  name=$1; shift
  /usr/bin/time -f "%U %S %M" -o "$DIR/$name.rusage" "$@"
  awk '{ printf "%.2f %d\n", $1 + $2, $3 }' "$DIR/$name.rusage" >"$DIR/$name.time"
  if [ -n "${CALLGRIND:-}" ]; then
    valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" 2>&1 |
      sed -n 's/.*Collected : \([0-9]*\).*/\1/p' >"$DIR/$name.ir"
  fi
}

t0=$(date +%s.%N)
measure whole "$SUMI" render "$SCENE" -W "$W" -H "$H" --threads 1 --quiet -o "$DIR/whole.png"
t1=$(date +%s.%N)
i=1
while [ "$i" -le "$N" ]; do   # two at a time
  measure "tile$i" "$SUMI" render "$SCENE" -W "$W" -H "$H" --threads 1 --quiet --tile "$i/$N" -o "$DIR/t$i.png" &
  j=$((i + 1))
  measure "tile$j" "$SUMI" render "$SCENE" -W "$W" -H "$H" --threads 1 --quiet --tile "$j/$N" -o "$DIR/t$j.png" &
  wait
  i=$((i + 2))
done
measure assemble "$SUMI" assemble "$DIR"/t*.png -o "$DIR/assembled.png"
t2=$(date +%s.%N)
cmp -s "$DIR/whole.png" "$DIR/assembled.png" && same=yes || same=NO

python3 - "$DIR" "$N" "$same" "$t0" "$t1" "$t2" "$W" "$H" <<'EOF'
import sys
d, n, same = sys.argv[1], int(sys.argv[2]), sys.argv[3]
t0, t1, t2 = map(float, sys.argv[4:7])
def read(name):
    cpu, kib = open("%s/%s.time" % (d, name)).read().split()
    return float(cpu), int(kib) / 1024
whole_cpu, whole_mib = read("whole")
tiles = [read("tile%d" % i) for i in range(1, n + 1)]
asm_cpu, asm_mib = read("assemble")
tile_cpu = sum(c for c, _ in tiles)
tile_mib = max(m for _, m in tiles)
print("tiles: bench/lines_teapot.npr at %sx%s, one thread a process" % (sys.argv[7], sys.argv[8]))
print("  %-26s %9s %10s" % ("", "CPU s", "peak MiB"))
print("  %-26s %9.2f %10.0f" % ("whole render", whole_cpu, whole_mib))
for i, (c, m) in enumerate(tiles, 1):
    print("  %-26s %9.2f %10.0f" % ("tile %d/%d" % (i, n), c, m))
print("  %-26s %9.2f %10.0f" % ("assemble", asm_cpu, asm_mib))
print("  tiles' CPU summed %.2f s = %.3fx the whole's (aim <= 1.15x); with assemble %.3fx"
      % (tile_cpu, tile_cpu / whole_cpu, (tile_cpu + asm_cpu) / whole_cpu))
print("  largest tile job %.0f MiB = %.3f of the whole's %.0f MiB (aim <= 0.25)"
      % (tile_mib, tile_mib / whole_mib, whole_mib))
import os
if os.path.exists("%s/whole.ir" % d):
    ir = lambda name: int(open("%s/%s.ir" % (d, name)).read())
    whole_ir, tile_ir = ir("whole"), sum(ir("tile%d" % i) for i in range(1, n + 1))
    print("  instructions: whole %.3fG, tiles summed %.3fG = %.3fx (assemble %.3fG)"
          % (whole_ir / 1e9, tile_ir / 1e9, tile_ir / whole_ir, ir("assemble") / 1e9))
print("  wall: whole %.1f s; tiles 2 at a time + assemble %.1f s; assembled = whole render: %s"
      % (t1 - t0, t2 - t1, same))
EOF
[ "$same" = yes ]
