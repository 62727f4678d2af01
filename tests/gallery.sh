#!/bin/sh
# The gallery page (scripts/gallery.py) in a real browser: the gallery is
# made into a scratch folder, its page is opened in headless Chromium with
# a check appended that lists every image (loaded or not, its natural
# size), and each must have loaded at the size of its PNG file; the page
# is also saved as a screenshot (build/test-out/gallery/screenshot.png).
# Ends with "N passed, N failed".
#
#   sh tests/gallery.sh SUMI

SUMI=$1
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=${OUT:-$ROOT/build/test-out/gallery}
rm -rf "$OUT"; mkdir -p "$OUT"
passed=0; failed=0
ok() { passed=$((passed + 1)); }
bad() { failed=$((failed + 1)); echo "FAIL gallery/$1"; }

CHROMIUM=$(command -v chromium || command -v chromium-browser)
[ -n "$CHROMIUM" ] || { echo "FAIL gallery: no chromium (make test-gallery installs it)"; echo "0 passed, 1 failed"; exit 1; }
# as root Chromium runs only without its sandbox; no GPU, no profile left behind
browse() {
  "$CHROMIUM" --headless=new --no-sandbox --disable-gpu --hide-scrollbars --no-first-run \
    --user-data-dir="$OUT/profile" --allow-file-access-from-files "$@" 2>>"$OUT/chromium.log"
}

python3 "$ROOT/scripts/gallery.py" "$SUMI" "$ROOT/examples" "$OUT/site" >"$OUT/gallery.log" 2>&1 ||
  { bad "scripts/gallery.py failed"; tail -5 "$OUT/gallery.log"; echo "$passed passed, $failed failed"; exit 1; }
page=$OUT/site/index.html
[ -s "$page" ] && ok || bad "no index.html"

# Every scene rendered appears on the page, with each of its images.
n_png=$(ls "$OUT/site"/*.png | wc -l)
n_img=$(grep -c '<img ' "$page")
[ "$n_png" = "$n_img" ] && [ "$n_img" -gt 10 ] && ok || bad "$n_img images on the page, $n_png rendered"

# The page with a check: at load, one line an image (src, complete,
# natural size) in a <pre id="check">, read back from the DOM.
sed 's|</body>|<script>\
window.addEventListener("load", function () {\
  var lines = [];\
  for (var i = 0; i < document.images.length; i++) {\
    var im = document.images[i];\
    lines.push(im.getAttribute("src") + " " + (im.complete \&\& im.naturalWidth > 0 ? "loaded" : "broken") + " " + im.naturalWidth + "x" + im.naturalHeight);\
  }\
  var pre = document.createElement("pre"); pre.id = "check"; pre.textContent = lines.join("\\n") + "\\nend";\
  document.body.appendChild(pre);\
});\
</script>\
</body>|' "$page" >"$OUT/site/check.html"
browse --dump-dom --virtual-time-budget=20000 "file://$OUT/site/check.html" >"$OUT/dom.html"
sed -n '/<pre id="check">/,/^end/p' "$OUT/dom.html" | sed 's/<pre id="check">//; s/<\/pre>//' | grep -v '^end' >"$OUT/check.txt"
[ "$(wc -l <"$OUT/check.txt")" = "$n_img" ] && ok || bad "the browser reported $(wc -l <"$OUT/check.txt") of $n_img images"
s=1
while read -r src state size; do
  want=$(python3 -c 'import struct,sys; d=open(sys.argv[1],"rb").read(24); print("%dx%d" % struct.unpack(">II", d[16:24]))' "$OUT/site/$src")
  if [ "$state" != loaded ] || [ "$size" != "$want" ]; then s=0; echo "  $src: $state, $size (the file is $want)"; fi
done <"$OUT/check.txt"
[ "$s" = 1 ] && ok || bad "an image did not load at its size"

# A screenshot of the page as it stands.
browse --screenshot="$OUT/screenshot.png" --window-size=1200,2400 "file://$page" >/dev/null
[ -s "$OUT/screenshot.png" ] && ok || bad "no screenshot"

echo "$passed passed, $failed failed"
