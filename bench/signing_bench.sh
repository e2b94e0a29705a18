#!/usr/bin/env bash
# The cost of signed fleet traffic (docs/security.md), in two figures:
#  1. signing and verifying one message (bench/auth_micro.cpp, Google
#     Benchmark; median of 3 repetitions) for an agent state, a data batch
#     and a tick reply: one MAC (the robot link), the fleet's per-link tags
#     for 1 to 301 receivers, and Ed25519 for comparison;
#  2. the multi-process fleet on maps/office (pap:4 with busy collectors,
#     3 cycles, 20 gather_agent processes over LCM), signed (--key-file)
#     against unsigned (--insecure): farm-bench, 9 pairs run in turn, median
#     wall time and the median of the pairs' ratios.
#
#   bench/signing_bench.sh GATHER   (make bench-signing; sends LCM multicast:
#                                    run it inside tools/netns-run)
set -euo pipefail
G=${1:?usage: bench/signing_bench.sh GATHER}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
if [ "${GATHER_NETNS:-}" != 1 ]; then
  echo "signing_bench: run me inside tools/netns-run (the fleet sends LCM multicast)" >&2
  exit 2
fi
command -v farm-bench >/dev/null || { echo "signing_bench: farm-bench not found (it times the paired runs)" >&2; exit 2; }

cmake -S "$here/src/gather_agent" -B "$here/build/bench_agent" -DCMAKE_BUILD_TYPE=Release -DGATHER_BUILD_BENCH=ON \
  -DBUILD_TESTING=OFF > /dev/null
cmake --build "$here/build/bench_agent" -j2 --target gather_auth_micro > /dev/null
echo "== sign / verify one message (libsodium $(pkg-config --modversion libsodium))"
echo "(BM_Sign/N, BM_Verify/N: one HMAC-SHA-512-256, the robot link; BM_SignTagged/N/R: the fleet's tags for R"
echo " receivers; BM_VerifyTagged/N: one receiver's own tag among 20; BM_Ed25519*: public-key signatures, for"
echo " comparison; a payload of N bytes; Time is per message)"
"$here/build/bench_agent/gather_auth_micro" --benchmark_repetitions=3 --benchmark_report_aggregates_only=true 2>/dev/null |
  grep -E '^(Benchmark|BM_.*_median)' 

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$G" plan "$here/maps/office.scenario.yaml" --config pap:4 --association off --out "$tmp/plan" > /dev/null
"$G" keygen "$tmp/fleet.key" > /dev/null
echo "== maps/office pap:4, 3 cycles, 20 agent processes over LCM: A signed, B unsigned (--insecure)"
farm-bench -n 9 --timeout 1800 --vs "$G run $tmp/plan --cycles 3 --out $tmp/unsigned --lcm --insecure" -- \
  "$G" run "$tmp/plan" --cycles 3 --out "$tmp/signed" --lcm --key-file "$tmp/fleet.key"
cmp "$tmp/signed/goals.csv" "$tmp/unsigned/goals.csv" && echo "goals.csv: signed and unsigned runs identical"
