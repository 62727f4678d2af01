#!/bin/sh
# make bench-eval: 10 million calls of a small user function inside a list
# comprehension, in sumi and in OpenSCAD 2021 (when installed), median of 3
# runs each, and the ratio. OpenSCAD refuses ranges of 1,000,000 elements or
# more, so both scripts nest two generators: 1000 x 10000.
set -e
SUMI=${1:-build/sumi}
DIR=build/bench
mkdir -p "$DIR"

cat >"$DIR/eval_calls.npr" <<'EOF'
fn f(x) = x * x + 1;
let v = [for (i = [0:999], j = [0:9999]) f(j)];
echo(len(v), v[len(v) - 1]);
EOF
cat >"$DIR/eval_calls.scad" <<'EOF'
function f(x) = x * x + 1;
v = [for (i = [0:999], j = [0:9999]) f(j)];
echo(len(v), v[len(v) - 1]);
EOF

# median_of CMD...: run 3 times, print the median wall time in seconds
median_of() {
  for i in 1 2 3; do
    /usr/bin/time -f "%e" -o "$DIR/eval.time" "$@" >/dev/null 2>"$DIR/eval.err" || { cat "$DIR/eval.err"; exit 1; }
    cat "$DIR/eval.time"
  done | sort -n | sed -n 2p
}

"$SUMI" check "$DIR/eval_calls.npr" 2>&1 | grep -q 'ECHO: 1e+7, 9.998e+7' || { echo "bench-eval: wrong result"; exit 1; }
sumi_s=$(median_of "$SUMI" check "$DIR/eval_calls.npr")
echo "eval: sumi     10M calls in a comprehension: median ${sumi_s} s over 3 runs (aim: under 1 s)"
if command -v openscad >/dev/null 2>&1; then
  scad_s=$(median_of openscad -o "$DIR/eval_calls.echo" "$DIR/eval_calls.scad")
  echo "eval: openscad 10M calls in a comprehension: median ${scad_s} s over 3 runs"
  python3 -c "import sys; a, b = float(sys.argv[1]), float(sys.argv[2]); print(f'eval: sumi is {b / max(a, 1e-3):.1f}x faster than OpenSCAD (aim: at least 10x)')" "$sumi_s" "$scad_s"
else
  echo "eval: openscad not installed; no comparison (make deps installs it)"
fi
