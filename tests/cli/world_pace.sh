#!/usr/bin/env bash
# gather_world_pace: a lone robot on maps/office from the OC down a corridor
# and back holds about the team speed (its top speed is 1.15 x the team
# speed; it never beats the top speed); bad input gives one line and exit
# status 2.
#
#   tests/cli/world_pace.sh PATH/TO/gather_world_pace
set -u
bin=${1:?usage: $0 PATH/TO/gather_world_pace}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
office="$here/../../maps/office.scenario.yaml"
fail=0
check() {  # name, expected status, expected stderr pattern, args...
  local name=$1 status=$2 pattern=$3
  shift 3
  local err out rc
  err=$(mktemp)
  out=$("$bin" "$@" 2>"$err")
  rc=$?
  if [ "$rc" -ne "$status" ]; then
    echo "FAIL $name: exit $rc, expected $status ($(head -c 300 "$err"))"
    fail=1
  elif [ "$status" -ne 0 ] && { [ "$(wc -l <"$err")" -ne 1 ] || ! grep -q -- "$pattern" "$err"; }; then
    echo "FAIL $name: expected one line matching '$pattern' on stderr, got: $(head -c 300 "$err")"
    fail=1
  else
    echo "ok   $name"
  fi
  rm -f "$err"
  LAST_OUT=$out
}
check "corridor and back" 0 "" "$office" 54.75 21.15 5.525 17.775
pace=$(printf '%s\n' "$LAST_OUT" | sed -n 's/^pace over the legs reached: \([0-9.]*\) of the team speed.*/\1/p')
if [ -z "$pace" ] || ! awk -v p="$pace" 'BEGIN { exit !(p > 0.85 && p <= 1.15) }'; then
  echo "FAIL corridor and back: pace '$pace' not in (0.85, 1.15]: $LAST_OUT"
  fail=1
else
  echo "ok   pace $pace in (0.85, 1.15]"
fi
check "point off the map" 2 "is not on the free space of" "$office" 1000 5
check "not a number" 2 "Y must be a finite number" "$office" 1 nan
check "no such scenario" 2 "nowhere.scenario.yaml" "$here/nowhere.scenario.yaml" 1 2
check "odd coordinates" 2 "usage" "$office" 3
exit $fail
