#!/usr/bin/env python3
"""Rendering work of two scenes at one size, in the same run:
  threshold_work.py RUNS SUMI W H SCENE_A SCENE_B
Each round renders A at W x H, A at 1 x 1, B at W x H and B at 1 x 1 (one
thread, --stats), the order turned every other round so a busy spell of the
shared machine falls on both. A scene's work is its W x H run less its 1 x 1
run (start-up, parsing, tessellation and the rest of what does not scale
with the image cancel); the ratio A / B is taken within each round. The PNG
encoding of the frame happens inside the tile pass (stats "write ... (cpu N
ms)"): a second ratio takes it off first, as a busy hatched image costs
zlib more than a flat toon one. Prints, as medians over the rounds:
  work_a work_b ratio work_a_less_png work_b_less_png ratio_less_png   (ms)"""
import re
import statistics
import subprocess
import sys
import time


def run(cmd):
    t = time.perf_counter()
    p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, check=True, text=True)
    took = time.perf_counter() - t
    m = re.search(r"^stats: write\s+[0-9.]+ ms\s+\(cpu ([0-9.]+) ms\)", p.stderr, re.M)
    return took * 1000, float(m.group(1)) if m else 0.0


def main():
    runs, sumi, w, h, a, b = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5], sys.argv[6]
    def cmd(scene, ww, hh):
        return [sumi, "render", scene, "-o", "build/bench/work.png", "-W", ww, "-H", hh, "--threads", "1",
                "--stats", "--quiet"]
    jobs = [cmd(a, w, h), cmd(a, "1", "1"), cmd(b, w, h), cmd(b, "1", "1")]
    for j in jobs:   # warm-up: page cache, libraries
        run(j)
    wa, wb, ratio, na, nb, nratio = [], [], [], [], [], []
    for r in range(runs):
        order = [0, 1, 2, 3] if r % 2 == 0 else [3, 2, 1, 0]
        t = {}
        for i in order:
            t[i] = run(jobs[i])
        work_a, work_b = t[0][0] - t[1][0], t[2][0] - t[3][0]
        less_a, less_b = work_a - t[0][1], work_b - t[2][1]
        wa.append(work_a); wb.append(work_b); ratio.append(work_a / work_b)
        na.append(less_a); nb.append(less_b); nratio.append(less_a / less_b)
    med = statistics.median
    print("%.1f %.1f %.2f %.1f %.1f %.2f" % (med(wa), med(wb), med(ratio), med(na), med(nb), med(nratio)))


main()
