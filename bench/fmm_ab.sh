#!/usr/bin/env bash
# FMM A/B: two builds of `gather` (e.g. before and after a refactor) solve the
# shared benchmark grids in turn on one pinned processor; per round each runs
# 5 solves and reports its fastest, and the table gives new/old of the minima
# and of the medians over the rounds. Both binaries must be built alike (both
# static plain CMake builds: catkin's shared libraries alone are 8-15% slower).
#
#   bench/fmm_ab.sh OLD_GATHER NEW_GATHER [ROUNDS]    (make bench-fmm-ab REF=<commit>)
set -euo pipefail
OLD=$1; NEW=$2; ROUNDS=${3:-8}
OUT=${OUT:-results/bench}
PY=${PYTHON:-/usr/bin/python3}  # with numpy (python3-numpy)
for b in "$OLD" "$NEW"; do [[ -x $b ]] || { echo "fmm_ab: $b is not an executable" >&2; exit 2; }; done
mkdir -p "$OUT/grids"
"$PY" ../shared/bench/make_grids.py "$OUT/grids" >/dev/null
printf '%-14s %5s %10s %10s %10s %10s %8s %8s\n' grid order old_min new_min old_med new_med min_ab med_ab
for case in "b_office2000 1" "b_office2000 2" "c_multi1000 1" "a_free2000 1"; do
  set -- $case
  g=$1; o=$2
  for i in $(seq "$ROUNDS"); do
    for side in old new; do
      bin=$OLD; [[ $side == new ]] && bin=$NEW
      ms=$(taskset -c 1 "$bin" fmm --map "$OUT/grids/$g.pgm" --sources-file "$OUT/grids/$g.src" --order "$o" --repeat 5 |
        grep -o 'ms=[0-9.]*' | cut -d= -f2 | sort -n | head -1)
      echo "$side $ms"
    done
  done | "$PY" -c "
import sys, statistics as st
d = {'old': [], 'new': []}
for line in sys.stdin:
    k, v = line.split(); d[k].append(float(v))
o, n = d['old'], d['new']
print('%-14s %5s %10.1f %10.1f %10.1f %10.1f %8.3f %8.3f' % ('$g', '$o', min(o), min(n), st.median(o), st.median(n),
      min(n) / min(o), st.median(n) / st.median(o)))
"
done
echo "(ms per solve; new/old below 1 is faster; ${ROUNDS} rounds, cpu 1)"
