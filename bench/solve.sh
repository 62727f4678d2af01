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
#   SOLVE_PATTERNS="N ..."  only these rows of states.csv (by number, e.g. "201 291 300")
#   SOLVE_JOBS=2           two lanes at once: the patterns of SOLVE_BIG variables or more
#                          (default 200000) one after another in one lane, the rest in the
#                          other (CPU times are per process; on a shared machine two lanes
#                          halve the wall time and leave the CPU times as they are)
#   FF_TIMEOUT=S           give up on a Flat-Folder run after S seconds of wall time (default 14400)
#
# Patterns run smallest first; each result line goes to build/bench/solve/results.tsv
# as it comes.
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
import csv, glob, os, statistics, subprocess, sys, threading, time
sumi, data, ff, out = sys.argv[1:5]
runs = int(os.environ.get("RUNS", "1"))
maxv = int(os.environ.get("SOLVE_MAX_VARIABLES", "0"))
only = set(os.environ.get("SOLVE_PATTERNS", "").split())
jobs = int(os.environ.get("SOLVE_JOBS", "1"))
big = int(os.environ.get("SOLVE_BIG", "200000"))
timeout = float(os.environ.get("FF_TIMEOUT", "14400"))
lock = threading.Lock()

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
        time.sleep(0.05)

rows = []
for r in list(csv.reader(open(os.path.join(data, "states.csv"))))[1:]:
    files = glob.glob(os.path.join(data, r[0] + "_*.fold"))
    nvars = int(r[-12])
    if files and not (maxv and nvars > maxv) and (not only or r[0] in only):
        rows.append((nvars, r, files[0]))
rows.sort(key=lambda x: (x[0], x[1][0]))
results = []          # (name, vars, sumi cpu, ff cpu or None, sumi rss, ff rss, count cpu, batch)
tsv = open(os.path.join(out, "results.tsv"), "w")
tsv.write("pattern\tvariables\tsumi_cpu_s\tff_cpu_s\tratio\tsumi_rss_mb\tff_rss_mb\tsumi_count_cpu_s\tff_batch_s\n")
print(f"{'pattern':<34} {'vars':>8} {'sumi s':>8} {'FF s':>8} {'ratio':>7} {'sumi MB':>8} {'FF MB':>7}", flush=True)

def one(nvars, r, f, lane):
    name = os.path.basename(f)[:-5][:34]
    ours, theirs = [], []
    for _ in range(runs):
        a = run([sumi, "fold", f, "--export", os.path.join(out, f"sumi_state{lane}.fold")])
        b = run(["node", os.path.join(ff, "gen_flatfolder_state.mjs"), os.path.join(ff, "src"), f,
                 os.path.join(out, f"ff_state{lane}.fold")], timeout)
        if a: ours.append(a)
        if b: theirs.append(b)
    batch = float(r[-2]) + float(r[-1])
    c = run([sumi, "fold", f, "--count"]) if ours and batch >= 0.1 else None   # below, a process start is the most of it
    cs = statistics.median(x[0] for x in ours) if ours else None
    cf = statistics.median(x[0] for x in theirs) if theirs else None
    ms = max(x[2] for x in ours) / 2**20 if ours else 0
    mf = max(x[2] for x in theirs) / 2**20 if theirs else 0
    with lock:
        results.append((name, nvars, cs, cf, ms, mf, c[0] if c else None, batch))
        if cs is None:
            print(f"{name:<34} {nvars:>8}   sumi failed", flush=True)
        elif cf is None:
            print(f"{name:<34} {nvars:>8} {cs:>8.3f}   Flat-Folder failed or timed out", flush=True)
        else:
            print(f"{name:<34} {nvars:>8} {cs:>8.3f} {cf:>8.3f} {cf / max(cs, 1e-6):>6.1f}x {ms:>8.0f} {mf:>7.0f}", flush=True)
        fmt = lambda x: "" if x is None else f"{x:.3f}"
        tsv.write(f"{name}\t{nvars}\t{fmt(cs)}\t{fmt(cf)}\t{fmt(cf / max(cs, 1e-6) if cs and cf else None)}\t"
                  f"{ms:.0f}\t{mf:.0f}\t{fmt(c[0] if c else None)}\t{batch:.3f}\n")
        tsv.flush()

def lane(todo, k):
    for x in todo:
        one(*x, k)

if jobs > 1:
    lanes = [[x for x in rows if x[0] >= big], [x for x in rows if x[0] < big]]
    threads = [threading.Thread(target=lane, args=(l, k)) for k, l in enumerate(lanes)]
    for t in threads: t.start()
    for t in threads: t.join()
else:
    lane(rows, 0)

print()
done = [x for x in results if x[2] is not None and x[3] is not None]
if done:
    ratios = [x[3] / max(x[2], 1e-6) for x in done]
    slow = [(x[0], x[3] / max(x[2], 1e-6)) for x in done if x[3] > 0.1]
    print(f"first state: median ratio {statistics.median(ratios):.1f}x over {len(ratios)} patterns (Flat-Folder CPU / sumi CPU)")
    if slow:
        worst = min(slow, key=lambda x: x[1])
        n10 = sum(1 for x in slow if x[1] >= 10)
        print(f"first state: {n10} of {len(slow)} patterns taking Flat-Folder over 0.1 s are 10x or more; "
              f"the least is {worst[0]} at {worst[1]:.1f}x (aim: 10x on every one)")
ok = [x for x in results if x[2] is not None]
if ok:
    largest = max(ok, key=lambda x: x[1])
    print(f"memory: peak RSS {largest[4]:.0f} MiB on the largest, {largest[0]} ({largest[1]} variables; aim: under 1 GB)"
          + (f"; Flat-Folder {largest[5]:.0f} MiB" if largest[5] else ""))
counts = [x for x in results if x[6] is not None]
if counts:
    slower = [x for x in counts if x[6] > x[7]]
    print(f"counting: sumi --count CPU vs Flat-Folder's batch setup + solve (states.csv, its author's machine; patterns it took 0.1 s or more): "
          f"median {statistics.median(x[7] / max(x[6], 1e-6) for x in counts):.1f}x; slower on {len(slower)} of {len(counts)}"
          + (": " + ", ".join(f"{x[0]} {x[6]:.2f} s vs {x[7]:.2f} s" for x in slower[:8]) if slower else ""))
PY
