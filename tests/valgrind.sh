#!/bin/sh
# make valgrind: render every example small under valgrind's memcheck; a
# memory error or a definite leak fails it (--error-exitcode). Possibly-lost
# blocks are the thread-local storage libraries keep until exit (not
# reported); glibc's one dlopen report is in tests/valgrind.supp.
#   sh tests/valgrind.sh build/sumi
SUMI=${1:-build/sumi}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT="$ROOT/build/valgrind"
mkdir -p "$OUT"
passed=0; failed=0; skipped=0
run() {   # NAME SCENE OUTPUT
  if valgrind -q --error-exitcode=99 --leak-check=full --show-possibly-lost=no \
       --errors-for-leak-kinds=definite --suppressions="$ROOT/tests/valgrind.supp" \
       "$SUMI" render "$2" -W 48 -o "$3" --quiet >"$OUT/$1.log" 2>&1; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1)); echo "FAIL valgrind/$1"; head -40 "$OUT/$1.log"
  fi
}
for f in "$ROOT"/examples/*.npr; do
  name=$(basename "$f" .npr)
  need=$(head -3 "$f" | sed -n 's|^// needs: *||p')
  if [ -n "$need" ] && [ ! -e "$need" ]; then skipped=$((skipped + 1)); continue; fi
  run "$name" "$f" "$OUT/$name.png"
done
# once through the OpenImageIO bridge (dlopen), to TIFF
run teapot_toon.tif "$ROOT/examples/teapot_toon.npr" "$OUT/teapot_toon.tif"
if [ "$skipped" -gt 0 ]; then echo "$passed passed, $failed failed, $skipped skipped"
else echo "$passed passed, $failed failed"; fi
[ "$failed" -eq 0 ]
