#!/usr/bin/env bash
# Every bad plan directory gives one clear line naming the file and exit status 2.
#
#   tests/cli/bad_plan.sh GATHER "COMMAND PREFIX"
#   e.g. tests/cli/bad_plan.sh build/gather "build/gather run --out /tmp/x"
#        tests/cli/bad_plan.sh build/gather "build/gather_agent --id 0 --lcm-url memq:// --plan"
#
# GATHER (the gather binary) makes a valid plan of maps/office (pap, 2
# collectors, the association off so that both serve workers and the plan
# has meetings and passes to break); each case breaks a copy of it. The
# prefix (split into words on spaces) is run with the broken plan directory
# appended. Each run must exit
# with status exactly 2, print nothing on stdout, print exactly one line on
# stderr naming the file (or directory) at fault, and finish within 20 s.
# Prints `ok   <case>` / `FAIL <case>: <why>` and `N passed, M failed`;
# exits 1 on any failure.
set -u

if [ $# -ne 2 ]; then
  echo "usage: $0 GATHER 'COMMAND PREFIX'  (the plan directory is appended)" >&2
  exit 2
fi
gather=$1
read -r -a prefix <<<"$2"
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
good="$tmp/good"
if ! "$gather" plan "$repo/maps/office.scenario.yaml" --config pap:2 --association off --out "$good" >/dev/null 2>"$tmp/plan.err"; then
  echo "$0: cannot make the valid plan: $(head -c 300 "$tmp/plan.err")" >&2
  exit 1
fi

passed=0
failed=0
# case NAME NEEDLE: runs the prefix on $tmp/NAME, expects NEEDLE in the one line.
check() {
  local name=$1 needle=$2
  timeout -k 2 20 "${prefix[@]}" "$tmp/$name" >"$tmp/out" 2>"$tmp/err" </dev/null
  local status=$? lines why=""
  lines=$(wc -l <"$tmp/err")
  if [ -s "$tmp/err" ] && [ "$(tail -c 1 "$tmp/err" | od -An -c | tr -d ' ')" != '\n' ]; then lines=$((lines + 1)); fi
  if [ "$status" -eq 124 ] || [ "$status" -eq 137 ]; then why="timed out after 20 s"
  elif [ "$status" -ne 2 ]; then why="exit status $status, expected 2: $(head -c 300 "$tmp/err")"
  elif [ -s "$tmp/out" ]; then why="stdout not empty: $(head -c 200 "$tmp/out" | head -n 1)"
  elif [ "$lines" -ne 1 ]; then why="$lines lines on stderr, expected 1: $(head -c 300 "$tmp/err" | tr '\n' '|')"
  elif ! grep -qF -- "$needle" "$tmp/err"; then why="stderr does not name $needle: $(head -c 300 "$tmp/err")"
  fi
  if [ -z "$why" ]; then echo "ok   $name"; passed=$((passed + 1)); else echo "FAIL $name: $why"; failed=$((failed + 1)); fi
}
copy() { rm -rf "$tmp/$1"; cp -r "$good" "$tmp/$1"; }
# edit NAME REGEX REPLACEMENT: the first match in NAME/plan.yaml.
edit() {
  /usr/bin/python3 -c 'import re, sys
p, pattern, new = sys.argv[1:]
s = open(p).read()
t = re.sub(pattern, new, s, count=1)
assert t != s, pattern
open(p, "w").write(t)' "$tmp/$1/plan.yaml" "$2" "$3"
}

check missing_dir "$tmp/missing_dir"
mkdir -p "$tmp/empty_dir"
check empty_dir "$tmp/empty_dir/plan.yaml"
copy garbage_yaml; printf 'this: [is not\n' >"$tmp/garbage_yaml/plan.yaml"
check garbage_yaml "$tmp/garbage_yaml/plan.yaml"
copy wrong_format; edit wrong_format 'format: gather-plan/2' 'format: gather-plan/9'
check wrong_format "$tmp/wrong_format/plan.yaml"
copy no_labels; rm "$tmp/no_labels/labels.png"
check no_labels "$tmp/no_labels/labels.png"
copy labels_8bit; cp "$repo/maps/office.png" "$tmp/labels_8bit/labels.png"
check labels_8bit "$tmp/labels_8bit/labels.png"
copy labels_truncated; head -c 60 "$good/labels.png" >"$tmp/labels_truncated/labels.png"
check labels_truncated "$tmp/labels_truncated/labels.png"
copy grid_factor; edit grid_factor 'grid_factor: 2' 'grid_factor: 1'
check grid_factor "$tmp/grid_factor/plan.yaml"
copy extra_agent; edit extra_agent 'routes:' '  - {id: 20, role: worker, segment: 19, collector: -1}\nroutes:'
check extra_agent "$tmp/extra_agent/plan.yaml"
copy no_scenario; edit no_scenario 'scenario: ' 'scenario: /nonexistent'
check no_scenario "$tmp/no_scenario/plan.yaml"
copy twice_an_id; edit twice_an_id '\{id: 1, role: collector' '{id: 0, role: collector'
check twice_an_id "$tmp/twice_an_id/plan.yaml"
copy collector_index; edit collector_index 'role: collector, segment: 0, collector: 1\}' 'role: collector, segment: 0, collector: 7}'
check collector_index "$tmp/collector_index/plan.yaml"
copy worker_of_nobody; edit worker_of_nobody 'role: worker, segment: 1, collector: -?[0-9]+' 'role: worker, segment: 1, collector: 5'
check worker_of_nobody "$tmp/worker_of_nobody/plan.yaml"
copy nan_waypoint; edit nan_waypoint '(waypoints:\n +- \[)[-0-9.e]+' '\1.nan'
check nan_waypoint "$tmp/nan_waypoint/plan.yaml"
copy zero_period; edit zero_period 'cycle_period_s: [0-9.e+]+' 'cycle_period_s: 0'
check zero_period "$tmp/zero_period/plan.yaml"
copy zero_tile; edit zero_tile 'area_tile_m: [0-9.e+]+' 'area_tile_m: 0'
check zero_tile "$tmp/zero_tile/plan.yaml"
copy tiny_tile; edit tiny_tile 'area_tile_m: [0-9.e+]+' 'area_tile_m: 1e-9'
check tiny_tile "$tmp/tiny_tile/plan.yaml"
copy no_interval; edit no_interval 'interval_s: [0-9.e+]+, ' ''
check no_interval "$tmp/no_interval/plan.yaml"
# Ids and counts against each other (docs/input_limits.md).
copy route_index; edit route_index '(routes:\n +- collector: )0' '\g<1>1'
check route_index "$tmp/route_index/plan.yaml"
copy collector_not_its_id; edit collector_not_its_id '\{id: 0, role: collector, segment: 0, collector: 0\}' '{id: 0, role: collector, segment: 0, collector: 1}'
check collector_not_its_id "$tmp/collector_not_its_id/plan.yaml"
copy worker_as_collector; edit worker_as_collector '\{id: ([0-9]+), role: worker, segment: [0-9]+, collector: -?[0-9]+\}' '{id: \1, role: collector, segment: 0, collector: 0}'
check worker_as_collector "$tmp/worker_as_collector/plan.yaml"
copy nan_pass; edit nan_pass 'passes_m: \[[-0-9.e]+' 'passes_m: [.nan'
check nan_pass "$tmp/nan_pass/plan.yaml"
copy far_waypoint; edit far_waypoint '(waypoints:\n +- \[)[-0-9.e]+' '\g<1>1e12'
check far_waypoint "$tmp/far_waypoint/plan.yaml"
copy huge_period; edit huge_period 'cycle_period_s: [0-9.e+]+' 'cycle_period_s: 1e300'
check huge_period "$tmp/huge_period/plan.yaml"
copy meeting_off_route; edit meeting_off_route 'at_m: [0-9.e+]+' 'at_m: 1e9'
check meeting_off_route "$tmp/meeting_off_route/plan.yaml"
copy segment_out_of_range; edit segment_out_of_range 'segments: \[[0-9]+' 'segments: [999'
check segment_out_of_range "$tmp/segment_out_of_range/plan.yaml"

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ] && [ "$passed" -gt 0 ]
