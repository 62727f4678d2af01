#!/usr/bin/env python3
"""Time two commands in alternation:
  pairs.py RUNS [--minus-stat NAME] -- CMD_A... -- CMD_B...

Each round runs A then B, swapping the order every other round, so slow
spells of a shared machine fall on both alike. Prints one line:
  median_a median_b median_of_differences median_of_stat median_of_net_differences
(seconds) of whole-run wall times, where a difference is A - B within the
same round. With --minus-stat, both commands print sumi's --stats table
on standard error; the fourth number is the median of their stage NAME
("image library": loading the image library, which sumi reports apart
from the work), and the fifth the median of the differences with each
run's NAME taken off first (less noisy when NAME's time is widely
spread). Without the option they are 0 and the plain median."""
import re
import statistics
import subprocess
import sys
import time


def run(cmd, stat):
    t = time.perf_counter()
    p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, check=True, text=True)
    took = time.perf_counter() - t
    if not stat:
        return took, 0.0
    m = re.search(r"^stats: %s\s+([0-9.]+) ms" % re.escape(stat), p.stderr, re.M)
    if not m:
        sys.exit("pairs.py: no 'stats: %s' line from %s" % (stat, " ".join(cmd)))
    part = float(m.group(1)) / 1000
    return took, part


def main():
    runs = int(sys.argv[1])
    rest = sys.argv[2:]
    stat = None
    if rest and rest[0] == "--minus-stat":
        stat, rest = rest[1], rest[2:]
    assert rest[0] == "--" and "--" in rest[1:], __doc__
    k = rest.index("--", 1)
    a, b = rest[1:k], rest[k + 1:]
    run(a, stat), run(b, stat)          # warm-up: page cache, libraries
    ta, tb, diff, net, parts = [], [], [], [], []
    for r in range(runs):
        if r % 2 == 0:
            x, px = run(a, stat); y, py = run(b, stat)
        else:
            y, py = run(b, stat); x, px = run(a, stat)
        ta.append(x); tb.append(y); diff.append(x - y); net.append((x - px) - (y - py)); parts += [px, py]
    print("%.4f %.4f %.4f %.4f %.4f" % (statistics.median(ta), statistics.median(tb), statistics.median(diff),
                                        statistics.median(parts), statistics.median(net)))


if __name__ == "__main__":
    main()
