#!/bin/sh
# make bench-csg: the difference of two closed meshes of 100k triangles
# each (latitude-longitude spheres as polyhedron literals, written in both
# languages by bench/gen_csg.py), exported to STL by sumi (CGAL's
# corefinement) and by OpenSCAD 2021 (CGAL's Nef polyhedra) in the same
# run: CPU time (user + system) of each, medians of 3 runs for sumi and of
# OPENSCAD_RUNS (default 1: one run takes minutes) for OpenSCAD, the ratio
# (aim: sumi at least 10x faster), and the two solids compared
# (tests/tools/stlcmp.py: volume and box, sumi's closed). CSG_TRIANGLES
# sets the size (default 100000).
set -e
SUMI=${1:-build/sumi}
DIR=build/bench
N=${CSG_TRIANGLES:-100000}
RUNS=${OPENSCAD_RUNS:-1}
mkdir -p "$DIR"
python3 bench/gen_csg.py "$N" "$DIR/csg.npr" "$DIR/csg.scad" | sed 's/^/csg: meshes of /'

# cpu_median RUNS OUT CMD...: run RUNS times, print the median CPU seconds
cpu_median() {
  runs=$1; shift
  k=0
  while [ $k -lt "$runs" ]; do
    /usr/bin/time -f "%U %S" -o "$DIR/csg.time" "$@" >"$DIR/csg.log" 2>&1 || { cat "$DIR/csg.log"; exit 1; }
    awk '{ print $1 + $2 }' "$DIR/csg.time"
    k=$((k + 1))
  done | sort -n | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'
}

sumi_s=$(cpu_median 3 "$SUMI" export "$DIR/csg.npr" -o "$DIR/csg.npr.stl")
echo "csg: sumi     difference, parse to STL: median ${sumi_s} s CPU over 3 runs"
if command -v openscad >/dev/null 2>&1; then
  scad_s=$(cpu_median "$RUNS" openscad -o "$DIR/csg.scad.stl" "$DIR/csg.scad")
  echo "csg: openscad difference, parse to STL: median ${scad_s} s CPU over $RUNS run(s)"
  python3 -c "import sys; a, b = float(sys.argv[1]), float(sys.argv[2]); print(f'csg: sumi is {b / max(a, 1e-3):.1f}x faster than OpenSCAD (aim: at least 10x)')" "$sumi_s" "$scad_s"
  python3 tests/tools/stlcmp.py "$DIR/csg.scad.stl" "$DIR/csg.npr.stl" --closed | sed 's/^/csg: /'
else
  echo "csg: openscad not installed; no comparison (make deps installs it)"
fi
