#!/usr/bin/env python3
"""Time two commands in alternation: `pairs.py RUNS -- CMD_A... -- CMD_B...`.

Each round runs A then B, swapping the order every other round, so slow
spells of a shared machine fall on both alike. Prints one line:
  median_a median_b median_of_differences   (seconds)
where a difference is A - B within the same round."""
import statistics
import subprocess
import sys
import time


def run(cmd):
    t = time.perf_counter()
    subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    return time.perf_counter() - t


def main():
    runs = int(sys.argv[1])
    rest = sys.argv[2:]
    assert rest[0] == "--" and "--" in rest[1:], __doc__
    k = rest.index("--", 1)
    a, b = rest[1:k], rest[k + 1:]
    run(a), run(b)                      # warm-up: page cache, libraries
    ta, tb, diff = [], [], []
    for r in range(runs):
        if r % 2 == 0:
            x = run(a); y = run(b)
        else:
            y = run(b); x = run(a)
        ta.append(x); tb.append(y); diff.append(x - y)
    print("%.4f %.4f %.4f" % (statistics.median(ta), statistics.median(tb), statistics.median(diff)))


if __name__ == "__main__":
    main()
