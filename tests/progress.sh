#!/bin/sh
# The progress line (io/progress.h): on a terminal (a pseudo-terminal,
# tests/tools/pty_run.py) a long render shows "N% of tiles, M:SS elapsed"
# redrawn in place, a frame run "frame k of n" too, the frame notes on
# lines of their own, and the line is gone at the end; --quiet shows
# nothing; off a terminal the output is what it always was. Ends with
# "N passed, N failed".
#
#   sh tests/progress.sh SUMI

SUMI=$1
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=${OUT:-$ROOT/build/test-out/progress}
SLOW=$ROOT/tests/hostile/signal/slow.npr   # 6000 x 6000: a second or more
PTY="python3 $ROOT/tests/tools/pty_run.py"
rm -rf "$OUT"; mkdir -p "$OUT"
passed=0; failed=0

ok() { passed=$((passed + 1)); }
bad() { failed=$((failed + 1)); echo "FAIL progress/$1"; }
# shown FILE: what the terminal got, carriage returns as <CR>, escapes as <ESC>
shown() { sed 's/\r/<CR>/g; s/\x1b/<ESC>/g' "$1"; }
# has NAME FILE REGEX: the terminal's text (shown) matches REGEX
has() { if shown "$2" | grep -Eq -- "$3"; then ok; else bad "$1"; shown "$2" | tail -c 400 | sed 's/^/  /'; echo; fi; }

# A frame run on a terminal.
$PTY "$OUT/frames.tty" "$SUMI" render "$SLOW" --frames 0:1 -o "$OUT/f_#.png"
st=$?
[ "$st" = 0 ] && ok || bad "a frame run on a terminal: exit $st"
line='<CR>sumi: frame [12] of 2, [0-9]+% of tiles, [0-9]+:[0-9]{2} elapsed(, ~[0-9]+:[0-9]{2} left)?<ESC>\[K'
has "the frame run's line" "$OUT/frames.tty" "$line"
has "the second frame's line" "$OUT/frames.tty" "<CR>sumi: frame 2 of 2, "
has "the line reaches 100% of the tiles" "$OUT/frames.tty" "frame 2 of 2, 100% of tiles"
# each note on a line of its own: after the line is taken off, or first
has "a frame's note on its own line" "$OUT/frames.tty" "(^|<CR><ESC>\[K)sumi: frame 1 \(clock 1\) -> $OUT/f_1.png<CR>$"
has "the line is gone at the end" "$OUT/frames.tty" "<CR><ESC>\[K$"
# nothing but lines drawn in place, the notes and their line ends
rest=$(shown "$OUT/frames.tty" | sed -E "s#$line##g; s#<CR><ESC>\[K##g; s#sumi: frame [01] \(clock [01]\) -> $OUT/f_[01].png<CR>##g" | tr -d '\n')
[ -z "$rest" ] && ok || bad "the terminal got more than the line and the notes: $rest"

# One image on a terminal: no frame count.
$PTY "$OUT/one.tty" "$SUMI" render "$SLOW" -o "$OUT/one.png"
has "one image's line" "$OUT/one.tty" "^<CR>sumi: [0-9]+% of tiles, [0-9]+:[0-9]{2} elapsed"
if shown "$OUT/one.tty" | grep -q "frame"; then bad "one image's line names a frame"; else ok; fi

# --quiet on a terminal: nothing at all.
$PTY "$OUT/quiet.tty" "$SUMI" render "$SLOW" --frames 0:1 --quiet -o "$OUT/q_#.png"
[ ! -s "$OUT/quiet.tty" ] && ok || bad "--quiet on a terminal printed: $(shown "$OUT/quiet.tty" | head -c 200)"

# Off a terminal: the notes alone, as before the line existed.
"$SUMI" render "$SLOW" -W 600 --frames 0:1 -o "$OUT/n_#.png" 2>"$OUT/notty.err" </dev/null | cat >"$OUT/notty.out"
printf 'sumi: frame 0 (clock 0) -> %s\nsumi: frame 1 (clock 1) -> %s\n' "$OUT/n_0.png" "$OUT/n_1.png" >"$OUT/notty.want"
cmp -s "$OUT/notty.err" "$OUT/notty.want" && [ ! -s "$OUT/notty.out" ] && ok || bad "off a terminal: $(cat "$OUT/notty.err")"
"$SUMI" render "$SLOW" -W 600 -o "$OUT/n.png" >"$OUT/notty1.out" 2>&1
[ ! -s "$OUT/notty1.out" ] && ok || bad "one image off a terminal printed: $(cat "$OUT/notty1.out")"

echo "$passed passed, $failed failed"
