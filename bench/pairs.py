#!/usr/bin/env python3
"""Time two commands in alternation:
  pairs.py RUNS [--minus-stat NAME] -- CMD_A... -- CMD_B...

Each round runs A then B, swapping the order every other round, so slow
spells of a shared machine fall on both alike. Prints one line:
  median_a median_b median_of_differences median_of_stat median_of_net_differences rss_a rss_b
(seconds) of whole-run wall times, where a difference is A - B within the
same round, then the median peak resident memory of each command's
process (MiB). With --minus-stat, both commands print sumi's --stats table
on standard error; the fourth number is the median of their stage NAME
("image library": the wait for loading the image library, which sumi
reports apart from the work, and leaves out when it does not load it),
and the fifth the median of the differences with each run's NAME taken
off first (less noisy when NAME's time is widely spread). Without the
option they are 0 and the plain median."""
import os
import re
import statistics
import subprocess
import sys
import time


def run(cmd, stat):
    """Wall seconds, the --stats stage's seconds, and peak RSS in MiB of one run."""
    t = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    err = p.stderr.read()
    _, status, usage = os.wait4(p.pid, 0)
    took = time.perf_counter() - t
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        sys.exit("pairs.py: %s failed (status %d)" % (" ".join(cmd), p.returncode))
    rss = usage.ru_maxrss / 1024.0
    if not stat:
        return took, 0.0, rss
    m = re.search(r"^stats: %s\s+([0-9.]+) ms" % re.escape(stat), err, re.M)
    part = float(m.group(1)) / 1000 if m else 0.0
    return took, part, rss


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
    ta, tb, diff, net, parts, ma, mb = [], [], [], [], [], [], []
    for r in range(runs):
        if r % 2 == 0:
            x, px, mx = run(a, stat); y, py, my = run(b, stat)
        else:
            y, py, my = run(b, stat); x, px, mx = run(a, stat)
        ta.append(x); tb.append(y); diff.append(x - y); net.append((x - px) - (y - py)); parts += [px, py]
        ma.append(mx); mb.append(my)
    print("%.4f %.4f %.4f %.4f %.4f %.1f %.1f" % (statistics.median(ta), statistics.median(tb),
                                                  statistics.median(diff), statistics.median(parts),
                                                  statistics.median(net), statistics.median(ma),
                                                  statistics.median(mb)))


if __name__ == "__main__":
    main()
