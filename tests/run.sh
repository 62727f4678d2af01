#!/bin/sh
# Runs every test suite and ends with the line CI reads: "N passed, N failed".
#
#   tests/parse/x.npr   -> x.ast  exact text of `sumi parse x.npr --ast`
#   tests/errors/x.npr  -> x.err  "exit: N", then stdout and stderr of `sumi check x.npr`
#   tests/eval/x.npr    -> x.out  "exit: N", then stdout and stderr of `sumi eval x.npr --scene`
#   tests/hostile/x.npr -> x.err  as errors, under a time and memory cap (below)
#   tests/render/x.npr  -> x.png  golden image, compared by imgcmp with a tolerance
#                       -> x.svg  (when present) exact text of `sumi render x.npr -o x.svg`
#                       with "// svg: TOLERANCE", x.svg drawn by rsvg-convert against x.png
#   docs/*.md ```npr blocks  each renders (small) with status 0 and no output
#   build/unit/test_*               C unit tests, each printing "N passed, N failed"
#   tests/tiles.sh      every example as tiles, assembled: the whole render's bytes
#   tests/frames.sh     frame steps, lists, --only and --resume
#   tests/progress.sh   the progress line on a terminal, none off one
#   tests/openscad.sh   tests/openscad/x.npr and x.scad: the same solid (STL volume, box)
#
# A line "// args: ..." among the first three gives extra options (and in
# tests/errors "// command: render" another subcommand); in render tests a line
# "// tolerance: --max-diff N --max-frac F" overrides the default tolerance,
# and (render, errors, eval) "// needs: /path" among the first three skips
# the case when the file a Debian package installs there is absent.
# UPDATE=1 rewrites the text snapshots, UPDATE_GOLDEN=1 the golden images.

BUILD=${BUILD:-build}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
# Sanitized builds: leaks inside system libraries we cannot mend.
LSAN_OPTIONS=suppressions=$ROOT/tests/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}
export LSAN_OPTIONS
SUMI="$ROOT/$BUILD/sumi"
OUT="$ROOT/$BUILD/test-out"
mkdir -p "$OUT"
passed=0; failed=0; skipped=0

pass() { passed=$((passed + 1)); }
fail() { failed=$((failed + 1)); echo "FAIL $1"; }

# Options and (errors suite) the subcommand, from the first lines of a case:
#   // command: render
#   // args: -o never.png
args_of() { head -3 "$1" | sed -n 's|^// args: *||p'; }
command_of() { head -3 "$1" | sed -n 's|^// command: *||p' | grep . || echo "$2"; }

# An existing suite folder with no cases is a broken suite.
cases() {
  if [ -d "$ROOT/tests/$1" ] && ! ls "$ROOT/tests/$1"/*.npr >/dev/null 2>&1; then
    fail "$1 (suite has no cases)"
  fi
}

# check_text SUITE EXPECTED_EXT COMMAND...  (runs in the suite folder)
check_text() {
  suite=$1; ext=$2; shift 2
  cases "$suite"
  for f in "$ROOT/tests/$suite"/*.npr; do
    [ -e "$f" ] || continue
    name=$(basename "$f" .npr)
    need=$(head -3 "$f" | sed -n 's|^// needs: *||p')
    if [ -n "$need" ] && [ ! -e "$need" ]; then
      skipped=$((skipped + 1)); echo "skip $suite/$name ($need is not installed)"; continue
    fi
    exp="$ROOT/tests/$suite/$name.$ext"
    got="$OUT/$suite.$name.$ext"
    # shellcheck disable=SC2046
    (cd "$ROOT/tests/$suite" && "$1" $(command_of "$f" "$2") "$name.npr" $(args_of "$f") $3 \
       >"$got.stdout" 2>"$got.stderr"
     echo "exit: $?" >"$got"; cat "$got.stdout" "$got.stderr" >>"$got")
    if [ "$suite" = parse ]; then tail -n +2 "$got" >"$got.body"; mv "$got.body" "$got"; fi
    if [ -n "$UPDATE" ]; then cp "$got" "$exp"; fi
    if [ -f "$exp" ] && cmp -s "$got" "$exp"; then pass
    else
      fail "$suite/$name"
      if [ -f "$exp" ]; then diff -u "$exp" "$got" | head -20; else echo "  (no $name.$ext: run make update-snapshots)"; fi
    fi
  done
}

check_text parse ast "$SUMI" parse --ast
check_text errors err "$SUMI" check
# A render that ends in an error writes no output file (the cases name
# theirs never.*).
left=$(ls "$ROOT/tests/errors" | grep '^never\.' || true)
if [ -z "$left" ]; then pass; else fail "errors: an error left an output file: $left"; (cd "$ROOT/tests/errors" && rm -f $left); fi
check_text eval out "$SUMI" eval --scene

# Hostile inputs: tests/hostile/x.npr -> x.err, as the errors suite, but
# each run under a wall-time cap (`// timeout: S`, default 20 s) and, outside
# sanitizer builds (ASan reserves terabytes of address space), an
# address-space cap (`// memory: MB`, default 4096), so a runaway fails its
# test instead of stalling the suite. `@OUT@` in a case is a fresh scratch
# folder (printed back as @OUT@; a case naming it runs as a copy there,
# where @OUT@ in the scene reads `.`, so its lines keep one length),
# `// setup: CMD` runs in it first, and `// command: render` picks the
# subcommand (default check).
hostile_meta() { head -8 "$1" | sed -n "s|^// $2: *||p" | head -1; }
cases hostile
for f in "$ROOT"/tests/hostile/*.npr; do
  [ -e "$f" ] || continue
  name=$(basename "$f" .npr)
  exp="$ROOT/tests/hostile/$name.err"
  got="$OUT/hostile.$name.err"
  scratch="$OUT/hostile.$name.dir"
  rm -rf "$scratch"; mkdir -p "$scratch"
  secs=$(hostile_meta "$f" timeout); mb=$(hostile_meta "$f" memory)
  setup=$(hostile_meta "$f" setup | sed "s|@OUT@|$scratch|g")
  cmd=$(hostile_meta "$f" command); cmd=${cmd:-check}
  args=$(hostile_meta "$f" args | sed "s|@OUT@|$scratch|g")
  vcap=""
  case "$BUILD" in *san*) ;; *) vcap="ulimit -v $(( ${mb:-4096} * 1024 ));" ;; esac
  [ -n "$setup" ] && (cd "$scratch" && sh -c "$setup") >/dev/null 2>&1
  dir="$ROOT/tests/hostile"   # a case naming @OUT@ runs as a copy in the scratch folder
  if grep -q @OUT@ "$f"; then sed "s|@OUT@|.|g" "$f" >"$scratch/$name.npr"; dir=$scratch; fi
  # shellcheck disable=SC2086
  (cd "$dir" && sh -c "$vcap exec timeout -k 2 ${secs:-20} \"\$@\"" sh \
     "$SUMI" $cmd "$name.npr" $args >"$got.stdout" 2>"$got.stderr"
   echo "exit: $?" >"$got"; cat "$got.stdout" "$got.stderr" | sed "s|$scratch|@OUT@|g" >>"$got")
  if [ -n "$UPDATE" ]; then cp "$got" "$exp"; fi
  if [ -f "$exp" ] && cmp -s "$got" "$exp"; then pass
  else
    fail "hostile/$name"
    if [ -f "$exp" ]; then diff -u "$exp" "$got" | head -20; else echo "  (no $name.err: run make update-snapshots)"; fi
  fi
done

# An interrupted render leaves nothing behind: SIGTERM or SIGINT while the
# PNG streams to its temporary removes it, and the target is never made.
# (perl resets SIGINT, which a shell ignores in the commands it starts in
# the background.)
interrupted() {
  sig=$1; dir="$OUT/interrupt.$sig.dir"
  rm -rf "$dir"; mkdir -p "$dir"
  perl -e '$SIG{INT} = "DEFAULT"; exec @ARGV' "$SUMI" render "$ROOT/tests/hostile/signal/slow.npr" \
    -o "$dir/out.png" --quiet 2>/dev/null &
  pid=$!
  k=0; while [ $k -lt 600 ] && ! ls "$dir" | grep -q tmp; do sleep 0.05; k=$((k + 1)); done
  kill -"$sig" $pid 2>/dev/null; wait $pid 2>/dev/null; status=$?
  left=$(ls "$dir")
  if [ $k -lt 600 ] && [ -z "$left" ] && [ $status -gt 128 ]; then pass
  else fail "hostile/interrupted by SIG$sig (exit $status, left: ${left:-nothing}, waited $k)"; fi
}
interrupted TERM
interrupted INT

# Render snapshots.
cases render
for f in "$ROOT"/tests/render/*.npr; do
  [ -e "$f" ] || continue
  name=$(basename "$f" .npr)
  golden="$ROOT/tests/render/$name.png"
  need=$(head -3 "$f" | sed -n 's|^// needs: *||p')
  if [ -n "$need" ] && [ ! -e "$need" ]; then
    skipped=$((skipped + 1)); echo "skip render/$name ($need is not installed)"; continue
  fi
  tol=$(sed -n 's|^// tolerance: *||p' "$f" | head -1)
  # shellcheck disable=SC2046
  if ! (cd "$ROOT/tests/render" && "$SUMI" render "$name.npr" -o "$OUT/$name.png" $(args_of "$f") >"$OUT/$name.log" 2>&1); then
    fail "render/$name (render failed)"; sed 's/^/  /' "$OUT/$name.log" | head -10; continue
  fi
  if [ -n "$UPDATE_GOLDEN" ]; then cp "$OUT/$name.png" "$golden"; fi
  # shellcheck disable=SC2086
  if [ -f "$golden" ] && "$ROOT/$BUILD/imgcmp" "$golden" "$OUT/$name.png" "$OUT/$name.diff.png" $tol >"$OUT/$name.cmp" 2>&1; then pass
  else
    fail "render/$name"; sed 's/^/  /' "$OUT/$name.cmp" 2>/dev/null
    echo "  got: $OUT/$name.png  diff: $OUT/$name.diff.png"
  fi
done

# Docs: every ```npr block of docs/*.md is a whole scene, run from where it
# stands (docs/: `../examples/...` reaches the examples' files): it must
# render small with status 0 and print nothing (a warning fails it too).
rm -rf "$OUT/docs"; mkdir -p "$OUT/docs"
ln -sfn "$ROOT/examples" "$OUT/examples"
for md in "$ROOT"/docs/*.md; do
  awk -v dir="$OUT/docs" -v base="$(basename "$md" .md)" '
    /^```npr *$/ { f = dir "/" base "_" NR ".npr"; next }
    /^```/ { if (f) close(f); f = ""; next }
    f { print > f }' "$md"
done
for f in "$OUT"/docs/*.npr; do
  [ -e "$f" ] || continue
  name=$(basename "$f" .npr)
  where="docs/${name%_*}.md:${name##*_}"
  if (cd "$OUT/docs" && "$SUMI" render "$name.npr" -o "$name.png" -W 96 -H 72 >"$name.log" 2>&1) &&
     [ ! -s "$OUT/docs/$name.log" ]; then pass
  else fail "$where (snippet)"; sed 's/^/  /' "$OUT/docs/$name.log" | head -10; fi
done

# SVG snapshots: tests/render/x.svg is the exact text of rendering x.npr to SVG.
for f in "$ROOT"/tests/render/*.svg; do
  [ -e "$f" ] || continue
  name=$(basename "$f" .svg)
  # shellcheck disable=SC2046
  (cd "$ROOT/tests/render" && "$SUMI" render "$name.npr" -o "$OUT/$name.svg" $(args_of "$ROOT/tests/render/$name.npr") >"$OUT/$name.svg.log" 2>&1)
  if [ -n "$UPDATE" ]; then cp "$OUT/$name.svg" "$f"; fi
  if cmp -s "$OUT/$name.svg" "$f"; then pass
  else fail "render/$name.svg"; diff -u "$f" "$OUT/$name.svg" | head -20; fi
done

# SVG against PNG: a render case with a line "// svg: --max-diff N --max-frac F"
# is also written as x.svg, drawn by a real SVG renderer (rsvg-convert) and
# compared with its golden x.png under that tolerance.
for f in "$ROOT"/tests/render/*.npr; do
  tol=$(sed -n 's|^// svg: *||p' "$f" | head -1)
  [ -n "$tol" ] || continue
  name=$(basename "$f" .npr)
  if ! command -v rsvg-convert >/dev/null; then skipped=$((skipped + 1)); continue; fi
  # shellcheck disable=SC2046
  if ! (cd "$ROOT/tests/render" && "$SUMI" render "$name.npr" -o "$OUT/$name.svg" $(args_of "$f") >"$OUT/$name.svg.log" 2>&1) ||
     ! rsvg-convert "$OUT/$name.svg" -o "$OUT/$name.svg.png" >>"$OUT/$name.svg.log" 2>&1; then
    fail "render/$name.svg (render failed)"; sed 's/^/  /' "$OUT/$name.svg.log" | head -10; continue
  fi
  # shellcheck disable=SC2086
  if "$ROOT/$BUILD/imgcmp" "$ROOT/tests/render/$name.png" "$OUT/$name.svg.png" "$OUT/$name.svg.diff.png" $tol >"$OUT/$name.svg.cmp" 2>&1; then pass
  else
    fail "render/$name.svg (against $name.png)"; sed 's/^/  /' "$OUT/$name.svg.cmp"
    echo "  got: $OUT/$name.svg.png  diff: $OUT/$name.svg.diff.png"
  fi
done

# Unit tests: each binary reports its own count.
for t in "$ROOT/$BUILD"/unit/test_*; do
  [ -x "$t" ] || continue
  line=$(cd "$ROOT" && "$t" 2>"$OUT/$(basename "$t").stderr" | tail -1)
  p=$(echo "$line" | sed -n 's/^\([0-9]*\) passed, \([0-9]*\) failed.*/\1/p')
  q=$(echo "$line" | sed -n 's/^\([0-9]*\) passed, \([0-9]*\) failed.*/\2/p')
  s=$(echo "$line" | sed -n 's/.*, \([0-9]*\) skipped.*/\1/p')
  if [ -z "$p" ]; then fail "unit/$(basename "$t") (crashed or printed no count)"; cat "$OUT/$(basename "$t").stderr" | head -20; continue; fi
  passed=$((passed + p)); failed=$((failed + q)); skipped=$((skipped + ${s:-0}))
  if [ "$q" != 0 ]; then echo "FAIL unit/$(basename "$t")"; head -20 "$OUT/$(basename "$t").stderr"; fi
done

# A suite in its own script, ending with its "N passed, N failed[, N
# skipped]" line: its counts are added, and its failures shown.
# subsuite NAME CMD...  (the log: $OUT/NAME.log)
subsuite() {
  name=$1; shift
  line=$("$@" 2>&1 | tee "$OUT/$name.log" | tail -1)
  p=$(echo "$line" | sed -n 's/^\([0-9]*\) passed, \([0-9]*\) failed.*/\1/p')
  q=$(echo "$line" | sed -n 's/^\([0-9]*\) passed, \([0-9]*\) failed.*/\2/p')
  s=$(echo "$line" | sed -n 's/.*, \([0-9]*\) skipped.*/\1/p')
  if [ -z "$p" ]; then fail "$name (printed no count)"; return; fi
  passed=$((passed + p)); failed=$((failed + q)); skipped=$((skipped + ${s:-0}))
  [ "$q" = 0 ] || grep -A4 FAIL "$OUT/$name.log" | head -30
}

# Tiles: every example rendered whole and as tiles in separate processes,
# stitched by `sumi assemble`, byte for byte the same (tests/tiles.sh).
subsuite tiles env OUT="$OUT/tiles" sh "$ROOT/tests/tiles.sh" "$SUMI"

# Frames as a scheduler's jobs run them: steps, lists, --only, --resume
# (tests/frames.sh).
subsuite frames env OUT="$OUT/frames" sh "$ROOT/tests/frames.sh" "$SUMI"

# The progress line on a (pseudo-)terminal, and nothing of it off one
# (tests/progress.sh).
subsuite progress env OUT="$OUT/progress" sh "$ROOT/tests/progress.sh" "$SUMI"

# The same solids as OpenSCAD: programs written both ways, their exported
# STL volumes and boxes compared (tests/openscad.sh; skips without openscad).
subsuite openscad env OUT="$OUT/openscad" sh "$ROOT/tests/openscad.sh" "$SUMI"

# Real crease patterns against Flat-Folder's counts (the fast rows; all of
# them: make check-cp). Skips cleanly without ../shared.
subsuite cp_check sh "$ROOT/tests/cp_check.sh" "$SUMI" 5000

if [ "$skipped" -gt 0 ]; then echo "$passed passed, $failed failed, $skipped skipped"
else echo "$passed passed, $failed failed"; fi
[ "$failed" -eq 0 ]
