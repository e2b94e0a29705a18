#!/usr/bin/env bash
# FMM benchmark: `gather fmm` against scikit-fmm on the three shared grids,
# in one run, one table. Builds nothing: give it the gather binary.
#
#   bench/fmm_bench.sh [GATHER_BIN]        (run from the repository root)
#
# GATHER_BIN defaults to catkin_ws/devel/lib/gather_core/gather.
# Environment: REPS (default 5) runs per measurement, median reported;
# OUT (default results/bench) for grids, logs and T fields.
set -euo pipefail

GATHER=${1:-catkin_ws/devel/lib/gather_core/gather}
REPS=${REPS:-5}
OUT=${OUT:-results/bench}
SHARED=../shared/bench

if [[ ! -x "$GATHER" ]]; then
  echo "fmm_bench: gather binary '$GATHER' not found (build first, or pass its path)" >&2
  exit 2
fi
if [[ ! -f "$SHARED/make_grids.py" || ! -f "$SHARED/bench_skfmm.py" ]]; then
  echo "fmm_bench: $SHARED/make_grids.py or bench_skfmm.py missing (run from the repository root)" >&2
  exit 2
fi
python3 -c "import numpy" 2>/dev/null || python3 -m pip install --quiet numpy
python3 -c "import skfmm" 2>/dev/null || python3 -m pip install --quiet scikit-fmm
if [[ ! -x /usr/bin/time ]]; then
  (apt-get update -qq && apt-get install -y -qq time) >/dev/null
fi

mkdir -p "$OUT/grids"
python3 "$SHARED/make_grids.py" "$OUT/grids" >/dev/null

# The process's own footprint (binary, shared libraries) on a 2x2 map, to subtract.
printf 'P5\n2 2\n255\n\377\377\377\377' >"$OUT/grids/tiny.pgm"
/usr/bin/time -f %M -o "$OUT/ours_base.rss" "$GATHER" fmm --map "$OUT/grids/tiny.pgm" --source 0,0 >/dev/null

GRIDS="a_free2000 b_office2000 c_multi1000"
for g in $GRIDS; do
  for o in 1 2; do
    /usr/bin/time -f %M -o "$OUT/ours_o${o}_$g.rss" \
      "$GATHER" fmm --map "$OUT/grids/$g.pgm" --sources-file "$OUT/grids/$g.src" --order "$o" \
      --repeat "$REPS" --out "$OUT/ours_o${o}_$g.npy" >"$OUT/ours_o${o}_$g.log"
  done
  python3 "$SHARED/bench_skfmm.py" "$OUT/grids/$g.pgm" --methods distance1,distance2 --reps "$REPS" \
    >"$OUT/skfmm_$g.log"
done

python3 - "$OUT" "$REPS" $GRIDS <<'PY'
import os, re, sys
import numpy as np

out, reps, grids = sys.argv[1], sys.argv[2], sys.argv[3:]

def kv(line):
    return dict(p.split("=", 1) for p in line.split() if "=" in p)

def read_pgm(path):
    data = open(path, "rb").read()
    m = re.match(rb"P5\s+(\d+)\s+(\d+)\s+(\d+)\s", data)
    w, h = int(m.group(1)), int(m.group(2))
    return np.frombuffer(data, np.uint8, w * h, m.end()).reshape(h, w)

def errors(grid, field):
    img = read_pgm(os.path.join(out, "grids", grid + ".pgm"))
    if (img == 0).any():
        return "NA", "NA"
    T = np.load(field)
    h, w = T.shape
    rr, cc = np.mgrid[0:h, 0:w]
    exact = np.full((h, w), np.inf)
    for line in open(os.path.join(out, "grids", grid + ".src")):
        r, c = map(int, line.split()[:2])
        np.minimum(exact, np.hypot(rr - r, cc - c), out=exact)
    ok = np.isfinite(T)
    e = np.abs(T - exact)[ok]
    return "%.3f" % e.mean(), "%.3f" % e.max()

base_kib = int(open(os.path.join(out, "ours_base.rss")).read().split()[-1])
rows = []
for g in grids:
    sk = {}
    for line in open(os.path.join(out, "skfmm_%s.log" % g)):
        if line.startswith("#"):
            skver = line.strip("# \n")
        if line.startswith("RESULT"):
            d = kv(line)
            sk[int(d["order"])] = d
    for o in (1, 2):
        lines = open(os.path.join(out, "ours_o%d_%s.log" % (o, g))).read().split("\n")
        last = kv([l for l in lines if l.startswith("cells=")][-1])
        run = kv([l for l in lines if l.startswith("run=")][-1])
        rss_kib = int(open(os.path.join(out, "ours_o%d_%s.rss" % (o, g))).read().split()[-1])
        cells = int(last["cells"])
        ours_cps = cells / (float(last["median_ms"]) / 1e3)
        me, mx = errors(g, os.path.join(out, "ours_o%d_%s.npy" % (o, g)))
        s = sk[o]
        sk_cps = float(s["cells_per_s"])
        rows.append([g, "gather", o, "%.1f" % float(last["median_ms"]), "%.2f" % (ours_cps / 1e6),
                     "%.1f" % (rss_kib / 1024.0), "%.1f" % ((rss_kib - base_kib) * 1024.0 / cells),
                     run["work_bytes_per_cell"],
                     me, mx, "%.1fx" % (ours_cps / sk_cps)])
        sk_mem = float(s["peak_rss_mib"]) - float(s["base_rss_mib"])
        rows.append([g, "skfmm", o, s["median_ms"], "%.2f" % (sk_cps / 1e6), s["peak_rss_mib"],
                     "%.1f" % (sk_mem * 1024 * 1024 / int(s["reached"])), "-",
                     s["mean_abs_err"] if s["mean_abs_err"] == "NA" else "%.3f" % float(s["mean_abs_err"]),
                     s["max_abs_err"] if s["max_abs_err"] == "NA" else "%.3f" % float(s["max_abs_err"]), "1.0x"])

head = ["grid", "impl", "order", "median_ms", "Mcells/s", "peak_MiB", "B/cell", "work_B/cell",
        "mean_err", "max_err", "vs_skfmm"]
print("# FMM benchmark: %s reps, median; %s; nproc=%d" % (reps, skver, os.cpu_count()))
print("# B/cell: (peak RSS - base) / reached cells; base = gather on a 2x2 map (%.1f MiB: binary and libraries),"
      % (base_kib / 1024.0))
print("#   for skfmm the interpreter with numpy and its input arrays (bench_skfmm.py's base_rss_mib)")
print("# work_B/cell: bytes held by the gather FMM workspace; errors in cells vs exact Euclidean (NA: obstacles)")
wid = [max(len(str(r[i])) for r in rows + [head]) for i in range(len(head))]
fmt = lambda r: "| " + " | ".join(str(v).rjust(wid[i]) for i, v in enumerate(r)) + " |"
print(fmt(head))
print("|" + "|".join("-" * (w + 2) for w in wid) + "|")
for r in rows:
    print(fmt(r))
PY
