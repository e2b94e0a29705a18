#!/usr/bin/env bash
# Flags with values no command can use (not a number, infinite, far beyond
# any map, control characters, 100 kB, an empty path): one line on stderr,
# at most 300 characters, exit status 2, within 10 s.
#
#   tests/cli/bad_flags.sh PATH/TO/gather
set -u
bin=${1:?usage: $0 PATH/TO/gather}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
office="$here/../../maps/office.scenario.yaml"
fail=0
check() {  # name, args...
  local name=$1
  shift
  local err rc lines width
  err=$(mktemp)
  timeout 10 "$bin" "$@" >/dev/null 2>"$err"
  rc=$?
  lines=$(wc -l <"$err")
  width=$(awk '{ if (length($0) > w) w = length($0) } END { print w + 0 }' "$err")
  if [ "$rc" -ne 2 ] || [ "$lines" -ne 1 ] || [ "$width" -gt 300 ]; then
    echo "FAIL $name: exit $rc, $lines line(s), widest $width: $(head -c 300 "$err")"
    fail=1
  else
    echo "ok   $name: $(cat "$err")"
  fi
  rm -f "$err"
}
check "radio --at nan" radio "$office" --at nan,1
check "radio --at inf" radio "$office" --at 1,inf
check "radio --at beyond any map" radio "$office" --at 1e300,-1e300
check "radio --at with a newline" radio "$office" --at "$(printf '1,2\nx')"
check "radio --at, 100 kB" radio "$office" --at "$(head -c 100000 /dev/zero | tr '\0' '7')"
check "radio --at off the map" radio "$office" --at 1000,5
# An empty path says so (it used to be "cannot open file", naming nothing).
check_empty() {  # name, args...
  local name=$1
  shift
  local err
  err=$(mktemp)
  timeout 10 "$bin" "$@" >/dev/null 2>"$err"
  if ! grep -q "the path is empty" "$err"; then
    echo "FAIL $name: $(head -c 300 "$err")"
    fail=1
  fi
  rm -f "$err"
  check "$name" "$@"
}
check_empty "info with an empty scenario path" info ""
check_empty "run with an empty plan directory" run "" --out "$(mktemp -d)/out"
# A scenario whose automatic request period (farthest point / team.speed)
# is over kMaxPeriod: gather plan refuses it up front.
slow=$(mktemp -d)
printf 'map: %s\noc: [1500.0, 1500.0]\nteam:\n  agents: 3\n  speed: 0.01\n' \
  "$here/../core/fixtures/bad/maps/kilometre_cells.yaml" >"$slow/slow.scenario.yaml"
check "plan with an automatic period over 1e5 s" plan "$slow/slow.scenario.yaml" --out "$slow/plan"
if ! "$bin" plan "$slow/slow.scenario.yaml" --out "$slow/plan" 2>&1 >/dev/null | grep -q "automatic request period"; then
  echo "FAIL plan with an automatic period over 1e5 s: the line does not say why"
  fail=1
fi
rm -rf "$slow"
exit $fail
