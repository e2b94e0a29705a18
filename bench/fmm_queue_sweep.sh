#!/usr/bin/env bash
# Queue kinds and bucket widths of the FMM solver side by side on the free
# 2000x2000 grid (central source): speed and error against the exact distance.
#
#   bench/fmm_queue_sweep.sh [GATHER_BIN]     (run from the repository root, after bench/fmm_bench.sh
#                                              or with OUT/grids made by ../shared/bench/make_grids.py)
set -euo pipefail
G=${1:-catkin_ws/devel/lib/gather_core/gather}
OUT=${OUT:-results/bench}
M="$OUT/grids/a_free2000.pgm"
[[ -f "$M" ]] || python3 ../shared/bench/make_grids.py "$OUT/grids" >/dev/null
for spec in "1 buckets 2" "1 buckets 1" "1 buckets 0.25" "1 sorted 0.02" "1 heap 0" \
            "2 sorted 0.02" "2 sorted 0.25" "2 heap 0" "2 buckets 1" "2 buckets 0.5" "2 buckets 0.25"; do
  set -- $spec
  last=$("$G" fmm --map "$M" --source 1000,1000 --order "$1" --queue "$2" --bucket-width "$3" --repeat 3 \
         --out "$OUT/sweep.npy" | tail -1)
  err=$(python3 -c "
import numpy as np
T = np.load('$OUT/sweep.npy'); r, c = np.mgrid[0:2000, 0:2000]; e = np.abs(T - np.hypot(r - 1000, c - 1000))
print('mean_err=%.3f max_err=%.3f' % (e.mean(), e.max()))")
  echo "order=$1 queue=$2 width=$3 $last $err"
done
