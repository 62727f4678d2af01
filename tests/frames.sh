#!/bin/sh
# Frames as a scheduler runs them (tests/data/frames/spin.npr, a box that
# turns with the clock): a step, a list and --only give each frame the
# bytes the whole run gives it (the clock is the animation's, not the
# job's); --resume skips frames and tiles whose files are whole, and
# renders again one cut short or missing, to the same bytes; a bad range
# writes nothing. Ends with "N passed, N failed".
#
#   sh tests/frames.sh SUMI

SUMI=$1
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=${OUT:-$ROOT/build/test-out/frames}
SCENE=$ROOT/tests/data/frames/spin.npr
rm -rf "$OUT"; mkdir -p "$OUT"
passed=0; failed=0

ok() { passed=$((passed + 1)); }
bad() { failed=$((failed + 1)); echo "FAIL frames/$1"; }

# same NAME A B...: frame files $OUT/A_NNNN.png equal the whole run's
same() {
  what=$1; run=$2; shift 2; s=1
  for fr in "$@"; do cmp -s "$OUT/all_$fr.png" "$OUT/${run}_$fr.png" || s=0; done
  if [ "$s" = 1 ]; then ok; else bad "$what: frames differ from the whole run's"; fi
}
# only FILES... : exactly these files (by name) are in $OUT/$dir
only() {
  what=$1; dir=$2; shift 2
  got=$(cd "$OUT/$dir" && ls | tr '\n' ' ')
  if [ "$got" = "$* " ] || [ "$got" = "$*" ]; then ok; else bad "$what: files are '$got', not '$*'"; fi
}

"$SUMI" render "$SCENE" --frames 0:8 --quiet -o "$OUT/all_####.png" || bad "the whole run failed"

# a step, a list, --only (the job of a scheduler's array, the index given)
mkdir -p "$OUT/step" "$OUT/list" "$OUT/only"
"$SUMI" render "$SCENE" --frames 0:8:4 --quiet -o "$OUT/step/s_####.png"
only "0:8:4 renders 0, 4 and 8" step s_0000.png s_0004.png s_0008.png
for f in 0000 0004 0008; do cp "$OUT/step/s_$f.png" "$OUT/step_$f.png"; done
same "0:8:4" step 0000 0004 0008
"$SUMI" render "$SCENE" --frames 8,0,3:4 --quiet -o "$OUT/list/l_####.png"
only "8,0,3:4 renders 0, 3, 4 and 8" list l_0000.png l_0003.png l_0004.png l_0008.png
for f in 0000 0003 0004 0008; do cp "$OUT/list/l_$f.png" "$OUT/list_$f.png"; done
same "a list" list 0000 0003 0004 0008
SLURM_ARRAY_TASK_ID=5
"$SUMI" render "$SCENE" --frames 0:8 --only "$SLURM_ARRAY_TASK_ID" --quiet -o "$OUT/only/o_####.png"
only "--only 5 renders frame 5 alone" only o_0005.png
cp "$OUT/only/o_0005.png" "$OUT/only_0005.png"
same "--only 5" only 0005

# a subdivided mesh across frames (tests/data/frames/subdiv.npr): the
# whole run keeps each refinement for the frames after it (subdiv.h's
# cache) and refines again where the control mesh changes; each frame has
# the bytes it has rendered alone (--only: one frame, no cache)
mkdir -p "$OUT/subdiv"
"$SUMI" render "$ROOT/tests/data/frames/subdiv.npr" --frames 0:4 --quiet -o "$OUT/subdiv/all_####.png" ||
  bad "the subdivided run failed"
s=1
for fr in 0 1 2 3 4; do
  "$SUMI" render "$ROOT/tests/data/frames/subdiv.npr" --frames 0:4 --only $fr --quiet -o "$OUT/subdiv/one_####.png"
  cmp -s "$OUT/subdiv/all_000$fr.png" "$OUT/subdiv/one_000$fr.png" || s=0
done
cmp -s "$OUT/subdiv/all_0002.png" "$OUT/subdiv/all_0003.png" && s=0   # the pulled corner shows
if [ "$s" = 1 ]; then ok; else bad "subdivided frames differ from the same frames rendered alone"; fi

# the same mesh kept across frames while the crease angle (frame 2) and
# the object's transform (frame 3) change (tests/data/frames/subdiv_turn.npr):
# what the line stage and the antialiasing keep with the refinement is
# made again for them, and each frame has the bytes it has alone
mkdir -p "$OUT/turn"
"$SUMI" render "$ROOT/tests/data/frames/subdiv_turn.npr" --frames 0:4 --quiet -o "$OUT/turn/all_####.png" ||
  bad "the turning run failed"
s=1
for fr in 0 1 2 3 4; do
  "$SUMI" render "$ROOT/tests/data/frames/subdiv_turn.npr" --frames 0:4 --only $fr --quiet -o "$OUT/turn/one_####.png"
  cmp -s "$OUT/turn/all_000$fr.png" "$OUT/turn/one_000$fr.png" || s=0
done
if [ "$s" = 1 ]; then ok; else bad "frames of a kept mesh differ from the same frames rendered alone"; fi

# an imported mesh under an orbiting camera (tests/data/frames/orbit.npr):
# the run reads the file and refines it at frame 0 only (--stats counts
# what the caches answered: 3 of 4 frames each, and nothing at frame 0),
# and each frame has the bytes it has rendered alone
mkdir -p "$OUT/orbit"
"$SUMI" render "$ROOT/tests/data/frames/orbit.npr" --frames 0:3 --stats --quiet -o "$OUT/orbit/all_####.png" \
  2>"$OUT/orbit/stats" || bad "the orbit run failed"
kept=$(grep -c 'meshes kept' "$OUT/orbit/stats")
last=$(grep -E '^stats: (eval|subdiv) ' "$OUT/orbit/stats" | tail -2 | sed 's/.*meshes kept //' | tr '\n' ' ')
if [ "$kept" = 6 ] && [ "$last" = "3 3 " ]; then ok
else bad "orbit: the caches answered $kept stage lines, at the end '$last' (not 6 lines ending '3 3 ')"; fi
s=1
for fr in 0 1 2 3; do
  "$SUMI" render "$ROOT/tests/data/frames/orbit.npr" --frames 0:3 --only $fr --quiet -o "$OUT/orbit/one_####.png"
  cmp -s "$OUT/orbit/all_000$fr.png" "$OUT/orbit/one_000$fr.png" || s=0
done
cmp -s "$OUT/orbit/all_0000.png" "$OUT/orbit/all_0001.png" && s=0   # the camera moves
if [ "$s" = 1 ]; then ok; else bad "orbit: frames differ from the same frames rendered alone"; fi

# a kept mesh whose transform changes (tests/data/frames/turn.npr): the
# world copies kept with the mesh serve only frames of their transform
mkdir -p "$OUT/turn"
"$SUMI" render "$ROOT/tests/data/frames/turn.npr" --frames 0:3 --quiet -o "$OUT/turn/all_####.png" || bad "the turn run failed"
s=1
for fr in 0 1 2 3; do
  "$SUMI" render "$ROOT/tests/data/frames/turn.npr" --frames 0:3 --only $fr --quiet -o "$OUT/turn/one_####.png"
  cmp -s "$OUT/turn/all_000$fr.png" "$OUT/turn/one_000$fr.png" || s=0
done
cmp -s "$OUT/turn/all_0000.png" "$OUT/turn/all_0002.png" || s=0   # the same transform
cmp -s "$OUT/turn/all_0000.png" "$OUT/turn/all_0001.png" && s=0   # a mirror
cmp -s "$OUT/turn/all_0000.png" "$OUT/turn/all_0003.png" && s=0   # a turn
if [ "$s" = 1 ]; then ok; else bad "turn: frames differ from the same frames rendered alone"; fi

# --resume: whole frames are skipped (their files untouched), one cut
# short and one missing are rendered again, to the whole run's bytes
mkdir -p "$OUT/resume"
cp "$OUT"/all_000[0-4].png "$OUT/resume/"
head -c 300 "$OUT/all_0002.png" >"$OUT/resume/all_0002.png"
rm "$OUT/resume/all_0003.png"
touch -d 2001-01-01 "$OUT"/resume/*.png
"$SUMI" render "$SCENE" --frames 0:8 --only 0:4 --resume -o "$OUT/resume/all_####.png" 2>"$OUT/resume.log"
if diff - "$OUT/resume.log" >"$OUT/resume.diff" <<LOG
sumi: $OUT/resume/all_0000.png is complete: not rendered again (--resume)
sumi: $OUT/resume/all_0001.png is complete: not rendered again (--resume)
sumi: frame 2 (clock 0.25) -> $OUT/resume/all_0002.png
sumi: frame 3 (clock 0.375) -> $OUT/resume/all_0003.png
sumi: $OUT/resume/all_0004.png is complete: not rendered again (--resume)
LOG
then ok; else bad "--resume: what it says"; sed 's/^/  /' "$OUT/resume.diff"; fi
old=$(find "$OUT/resume" -name '*.png' ! -newermt 2001-01-02 | wc -l)
[ "$old" = 3 ] && ok || bad "--resume: $old of the 3 whole frames left untouched"
s=1; for f in 0 1 2 3 4; do cmp -s "$OUT/all_000$f.png" "$OUT/resume/all_000$f.png" || s=0; done
[ "$s" = 1 ] && ok || bad "--resume: frames differ from the whole run's"

# --resume of tiles: a tile job run again skips its whole tile
"$SUMI" render "$SCENE" --tile 2/3 -o "$OUT/t2.png"
cp "$OUT/t2.png" "$OUT/t2.whole.png"
"$SUMI" render "$SCENE" --tile 2/3 -o "$OUT/t2.png" --resume 2>"$OUT/tile.log"
grep -q "t2.png is complete: not rendered again" "$OUT/tile.log" && ok || bad "--resume of a whole tile renders it again"
head -c 200 "$OUT/t2.whole.png" >"$OUT/t2.png"
"$SUMI" render "$SCENE" --tile 2/3 -o "$OUT/t2.png" --resume 2>"$OUT/tile.log"
cmp -s "$OUT/t2.png" "$OUT/t2.whole.png" && [ ! -s "$OUT/tile.log" ] && ok || bad "--resume of a tile cut short"

# --aov passes are written before the image, so a whole image has them
"$SUMI" render "$SCENE" --frames 1 --aov depth --quiet -o "$OUT/aov_#.png"
[ -f "$OUT/aov_1.png" ] && [ -f "$OUT/aov_1.depth.exr" ] && ok || bad "--aov: $(ls "$OUT" | grep aov_ | tr '\n' ' ')"

# a bad range writes nothing, not even its first frames
mkdir -p "$OUT/bad"
for spec in 5:2 0:4,3:1 0:4:0; do
  "$SUMI" render "$SCENE" --frames $spec -o "$OUT/bad/b_####.png" 2>/dev/null
  st=$?
  if [ "$st" = 2 ] && [ -z "$(ls "$OUT/bad")" ]; then ok; else bad "--frames $spec: exit $st, left $(ls "$OUT/bad")"; fi
done

echo "$passed passed, $failed failed"
