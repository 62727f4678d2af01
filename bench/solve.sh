#!/bin/sh
# make bench-solve: the layer-order solver against Flat-Folder (J. Ku, MIT;
# its source and driver in $SUMI_SHARED/peers/flat-folder, run with node)
# on the real crease patterns of $SUMI_SHARED/data/cp, in the same run.
#
# Time to a first full state: `sumi fold P --export S.fold` against
# `node gen_flatfolder_state.mjs src P S.fold` (import, fold, cells,
# constraints, forced orders, one state of every component, FOLD export),
# alternating, RUNS times each (default 1), median CPU time (user + sys:
# steadier than wall on a shared machine); then each ratio and their
# median, and peak RSS of the largest pattern. Counting: `sumi fold P
# --count` against Flat-Folder's batch times in states.csv (setup + solve).
#
#   SOLVE_MAX_VARIABLES=N  leave out patterns with more face pairs (default: none)
#   FF_TIMEOUT=S           give up on a Flat-Folder run after S seconds (default 1200)
set -e
SUMI=${1:-build/sumi}
SHARED=${SUMI_SHARED:-../shared}
DATA="$SHARED/data/cp"
FF="$SHARED/peers/flat-folder"
if [ ! -f "$DATA/states.csv" ] || [ ! -f "$FF/gen_flatfolder_state.mjs" ]; then
  echo "bench-solve: $SHARED/data/cp or $SHARED/peers/flat-folder is absent; skipped"
  exit 0
fi
command -v node >/dev/null || { echo "bench-solve: node is not installed (apt-get install nodejs); skipped"; exit 0; }
DIR=$(dirname "$SUMI")/bench/solve
mkdir -p "$DIR"
python3 - "$SUMI" "$DATA" "$FF" "$DIR" <<'PY'
import csv, glob, os, statistics, subprocess, sys, time
sumi, data, ff, out = sys.argv[1:5]
runs = int(os.environ.get("RUNS", "1"))
maxv = int(os.environ.get("SOLVE_MAX_VARIABLES", "0"))
timeout = float(os.environ.get("FF_TIMEOUT", "1200"))

def run(argv, limit=None):
    """CPU seconds (user + sys), wall seconds and peak RSS bytes of one run, or None."""
    t0 = time.perf_counter()
    p = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        _, status, ru = os.wait4(p.pid, 0) if limit is None else wait_limited(p, limit)
    except subprocess.TimeoutExpired:
        return None
    if status != 0:
        return None
    return ru.ru_utime + ru.ru_stime, time.perf_counter() - t0, ru.ru_maxrss * 1024

def wait_limited(p, limit):
    end = time.time() + limit
    while True:
        pid, status, ru = os.wait4(p.pid, os.WNOHANG)
        if pid:
            return pid, status, ru
        if time.time() > end:
            p.kill(); os.wait4(p.pid, 0)
            raise subprocess.TimeoutExpired(p.args, limit)
        time.sleep(0.02)

rows = list(csv.reader(open(os.path.join(data, "states.csv"))))[1:]
ratios, first_rows, count_rows, largest = [], [], [], None
print(f"{'pattern':<34} {'vars':>8} {'sumi s':>8} {'FF s':>8} {'ratio':>7}")
for r in rows:
    num, nvars = r[0], int(r[-12])
    files = glob.glob(os.path.join(data, num + "_*.fold"))
    if not files or (maxv and nvars > maxv):
        continue
    f = files[0]
    name = os.path.basename(f)[:-5][:34]
    ours, theirs = [], []
    for _ in range(runs):
        a = run([sumi, "fold", f, "--export", os.path.join(out, "sumi_state.fold")])
        b = run(["node", os.path.join(ff, "gen_flatfolder_state.mjs"), os.path.join(ff, "src"), f,
                 os.path.join(out, "ff_state.fold")], timeout)
        if a: ours.append(a)
        if b: theirs.append(b)
    if not ours:
        print(f"{name:<34} {nvars:>8}   sumi failed"); continue
    cs = statistics.median(x[0] for x in ours)
    if largest is None or nvars > largest[0]:
        largest = (nvars, name, max(x[2] for x in ours))
    if not theirs:
        print(f"{name:<34} {nvars:>8} {cs:>8.3f}   Flat-Folder failed or timed out"); continue
    cf = statistics.median(x[0] for x in theirs)
    ratio = cf / max(cs, 1e-6)
    ratios.append(ratio)
    first_rows.append((name, cf, ratio))
    print(f"{name:<34} {nvars:>8} {cs:>8.3f} {cf:>8.3f} {ratio:>6.1f}x", flush=True)
    batch = float(r[-2]) + float(r[-1])
    c = run([sumi, "fold", f, "--count"]) if batch >= 0.1 else None   # below, a process start is the most of it
    if c:
        count_rows.append((name, c[0], batch))
print()
if ratios:
    slow = [x for x in first_rows if x[1] > 0.1]
    worst = min(slow, key=lambda x: x[2]) if slow else None
    print(f"first state: median ratio {statistics.median(ratios):.1f}x over {len(ratios)} patterns (Flat-Folder CPU / sumi CPU)")
    if worst:
        n10 = sum(1 for x in slow if x[2] >= 10)
        print(f"first state: {n10} of {len(slow)} patterns taking Flat-Folder over 0.1 s are 10x or more; "
              f"the least is {worst[0]} at {worst[2]:.1f}x (aim: 10x on every one)")
if largest:
    print(f"memory: peak RSS {largest[2] / 2**20:.0f} MiB on the largest, {largest[1]} ({largest[0]} variables; aim: under 1 GB)")
if count_rows:
    slower = [x for x in count_rows if x[1] > x[2]]
    print(f"counting: sumi --count CPU vs Flat-Folder's batch setup + solve (states.csv, its author's machine; patterns it took 0.1 s or more): "
          f"median {statistics.median(b / max(a, 1e-6) for _, a, b in count_rows):.1f}x; slower on {len(slower)} of {len(count_rows)}"
          + (": " + ", ".join(f"{n} {a:.2f} s vs {b:.2f} s" for n, a, b in slower[:8]) if slower else ""))
PY
