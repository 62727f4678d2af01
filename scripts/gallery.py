#!/usr/bin/env python3
"""The gallery: every scene in examples/ rendered into docs/gallery/, and
docs/gallery/index.html, a contact sheet of them: each image (an
animation's frames side by side) at its own size, its scene file, the
opening comment of the scene, the styles it shows (read from the
evaluated scene, `sumi eval --scene`), the papers they come from and the
render's time (CPU seconds, user and system, of the `sumi render`
process, and wall seconds).

An example's first lines may say `// needs: FILE` (skipped when FILE, a
Debian package's data, is absent) or `// frames: A:B` (an animation: one
image a frame, NAME_####.png).

    python3 scripts/gallery.py SUMI [EXAMPLES_DIR [OUT_DIR]]
"""
import glob
import html
import os
import re
import resource
import struct
import subprocess
import sys
import time

# The papers (docs: ../shared/design/algorithms.md's table), by what a
# scene's evaluated styles show.
PAPERS = {
    "mitani": "Mitani, Rendering method for flat origami",
    "ukiyoe": "Brown & Arandjelović, Making Japanese Ukiyo-e Art 3D in Real-Time",
    "veryovka": "Veryovka, Animation with threshold textures",
    "yeh": "Yeh, Automatic Rendering of 3D Animal Models in Chinese Painting Style",
    "toon": "CSE 167 lecture, Toon Shading and Surface Patches",
}
# A shading model or line stroke -> the paper it comes from (None: none).
SOURCE = {
    "toon": "toon", "threshold": "veryovka", "bokashi": "ukiyoe", "ink": "yeh",
    "origami": "mitani", "ribbon": "ukiyoe", "brush": "yeh", "noise": "ukiyoe",
    "pattern": "ukiyoe", "xuan": "yeh",
}


def header(path, key):
    """The value of a `// key: value` line among the first three, or None."""
    with open(path, encoding="utf-8") as f:
        for line in f.readlines()[:3]:
            m = re.match(r"//\s*%s:\s*(.*\S)" % key, line)
            if m:
                return m.group(1)
    return None


def description(path):
    """The scene's opening comment (its `needs:` and `frames:` lines left out)."""
    words = []
    with open(path, encoding="utf-8") as f:
        for line in f:
            if not line.startswith("//"):
                break
            text = line[2:].strip()
            if re.match(r"(needs|frames):", text):
                continue
            words.append(text)
    return " ".join(words)


def styles_of(sumi, path):
    """The styles a scene shows, from its evaluated form: shading models,
    line strokes other than plain, the block's noise, a paper sheet."""
    out = subprocess.run([sumi, "eval", path, "--scene"], cwd=os.path.dirname(path),
                         capture_output=True, text=True).stdout
    found = []
    for line in out.splitlines():
        m = re.match(r"style\[\d+\]\.shade\.kind (.*)", line)
        if m:
            found.append(m.group(1))
        m = re.match(r"style\[\d+\]\.lines\.stroke (\w+)", line)
        if m and m.group(1) != "plain":
            found.append(m.group(1) + " lines" if m.group(1) == "ribbon" else m.group(1) + " strokes")
        m = re.match(r"style\[\d+\]\.noise\.amount (\S+)", line)
        if m and float(m.group(1)) > 0:
            found.append("noise")
        if re.match(r"style\[\d+\]\.pattern\.image ", line):
            found.append("pattern")
        m = re.match(r'output\.sheet "(\w+)"', line)
        if m:
            found.append(m.group(1) + " paper")
    return sorted(set(found))


def papers_of(styles):
    keys = []
    for s in styles:
        k = SOURCE.get(s.split()[0])
        if k and k not in keys:
            keys.append(k)
    return [PAPERS[k] for k in sorted(keys, key=list(PAPERS).index)]


def png_size(path):
    """A PNG's width and height, from its IHDR chunk."""
    with open(path, "rb") as f:
        head = f.read(24)
    return struct.unpack(">II", head[16:24])


def render(sumi, path, out_dir):
    """Render the example; its images (file names), CPU and wall seconds."""
    name = os.path.splitext(os.path.basename(path))[0]
    frames = header(path, "frames")
    if frames:
        for old in glob.glob(os.path.join(out_dir, name + "_[0-9][0-9][0-9][0-9].png")):
            os.remove(old)
        argv = [sumi, "render", path, "--frames", frames, "--quiet", "-o",
                os.path.join(out_dir, name + "_####.png")]
    else:
        argv = [sumi, "render", path, "-o", os.path.join(out_dir, name + ".png")]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    subprocess.run(argv, check=True)
    wall = time.monotonic() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if frames:
        images = sorted(os.path.basename(p) for p in
                        glob.glob(os.path.join(out_dir, name + "_[0-9][0-9][0-9][0-9].png")))
    else:
        images = [name + ".png"]
    return images, cpu, wall


PAGE_HEAD = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>sumi gallery</title>
<style>
body { font: 15px/1.45 system-ui, sans-serif; margin: 2em auto; max-width: 1100px; padding: 0 1em; color: #1a1a1a; background: #faf8f3; }
h1 { font-weight: 600; }
figure { margin: 0 0 2.5em; padding-bottom: 1.5em; border-bottom: 1px solid #ddd; }
.images { display: flex; flex-wrap: wrap; gap: 6px; }
.images img { max-width: 100%; height: auto; background: #fff; box-shadow: 0 1px 3px #0002; }
figcaption h2 { font-size: 1.05em; margin: .6em 0 .2em; }
figcaption p { margin: .2em 0; }
.meta { color: #555; font-size: .92em; }
code { font-size: .95em; }
</style>
</head>
<body>
<h1>sumi gallery</h1>
<p>Every scene in <code>examples/</code>, as <code>make gallery</code> rendered it
(each image at its own size; an animation's frames side by side). Styles are read
from the evaluated scene; times are the render's CPU time (user and system) and wall
time on the machine that made this page.</p>
"""


def figure(name, scene_rel, images, sizes, desc, styles, papers, cpu, wall):
    """One example's figure: its images, scene, description, styles, papers, time."""
    imgs = "\n".join(
        '<img src="%s" width="%d" height="%d" alt="%s">' % (html.escape(img), w, h, html.escape(img))
        for img, (w, h) in zip(images, sizes))
    return """<figure id="%s">
<div class="images">
%s
</div>
<figcaption>
<h2><a href="%s"><code>%s</code></a></h2>
<p>%s</p>
<p class="meta">Styles: %s.<br>Paper: %s.<br>Render: %.2f s CPU, %.2f s wall%s.</p>
</figcaption>
</figure>
""" % (html.escape(name), imgs, html.escape(scene_rel), html.escape("examples/" + name + ".npr"), html.escape(desc),
       html.escape(", ".join(styles) or "plain shading"), html.escape("; ".join(papers) or "none (plain shading)"),
       cpu, wall, (" for %d frames" % len(images)) if len(images) > 1 else "")


def main():
    sumi = os.path.abspath(sys.argv[1])
    examples = os.path.abspath(sys.argv[2] if len(sys.argv) > 2 else "examples")
    out_dir = os.path.abspath(sys.argv[3] if len(sys.argv) > 3 else "docs/gallery")
    os.makedirs(out_dir, exist_ok=True)
    parts, skipped = [], []
    for path in sorted(glob.glob(os.path.join(examples, "*.npr"))):
        name = os.path.splitext(os.path.basename(path))[0]
        need = header(path, "needs")
        if need and not os.path.exists(need):
            print("skip %s (no %s)" % (path, need))
            skipped.append((name, need))
            continue
        print("render %s" % path, flush=True)
        images, cpu, wall = render(sumi, path, out_dir)
        sizes = [png_size(os.path.join(out_dir, img)) for img in images]
        styles = styles_of(sumi, path)
        scene_rel = os.path.relpath(path, out_dir)
        parts.append(figure(name, scene_rel, images, sizes, description(path), styles, papers_of(styles),
                            cpu, wall))
    page = PAGE_HEAD + "".join(parts)
    if skipped:
        page += "<p class=\"meta\">Not rendered here (a package's data absent): %s.</p>\n" % html.escape(
            ", ".join("%s (%s)" % s for s in skipped))
    page += "</body>\n</html>\n"
    with open(os.path.join(out_dir, "index.html"), "w", encoding="utf-8") as f:
        f.write(page)
    print("wrote %s (%d scenes)" % (os.path.join(out_dir, "index.html"), len(parts)))


main()
