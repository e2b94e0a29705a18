#!/usr/bin/env bash
# Every bad input gives one clear line and exit status 2.
#
#   tests/cli/bad_input.sh "COMMAND PREFIX" [MORE PREFIX WORDS...]
#   e.g. tests/cli/bad_input.sh "build/gather info"
#        tests/cli/bad_input.sh build/gather_agent --id 0
#
# The prefix (a single argument is split into words on spaces; several
# arguments are used as they are) is run with each bad scenario of
# tests/core/fixtures/bad/cases.txt appended as the last argument. Each run must:
# exit with status exactly 2, print nothing on stdout, print exactly one line on
# stderr, name the offending file in it, and finish within 10 s.
# Prints `ok   <case>` / `FAIL <case>: <why>` per case and `N passed, M failed`;
# exits 1 on any failure.
set -u

if [ $# -lt 1 ]; then
  echo "usage: $0 'COMMAND PREFIX' [WORDS...]  (the scenario path is appended)" >&2
  exit 2
fi
if [ $# -eq 1 ]; then
  read -r -a prefix <<<"$1"  # one string: split into words on spaces
else
  prefix=("$@")              # several arguments: taken as they are
fi

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
bad="$here/../core/fixtures/bad"
list="$bad/cases.txt"
if [ ! -f "$list" ]; then
  echo "$0: $list: cannot open file" >&2
  exit 2
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

passed=0
failed=0
while read -r case_file named _; do
  case "$case_file" in '' | '#'*) continue ;; esac
  name=${case_file%.yaml}
  scenario="$bad/cases/$case_file"
  timeout -k 2 10 "${prefix[@]}" "$scenario" >"$tmp/out" 2>"$tmp/err" </dev/null
  status=$?
  lines=$(wc -l <"$tmp/err")
  # A last line without a newline still counts as a line.
  if [ -s "$tmp/err" ] && [ "$(tail -c 1 "$tmp/err" | od -An -c | tr -d ' ')" != '\n' ]; then
    lines=$((lines + 1))
  fi
  why=""
  if [ "$status" -eq 124 ] || [ "$status" -eq 137 ]; then
    why="timed out after 10 s"
  elif [ "$status" -ne 2 ]; then
    why="exit status $status, expected 2"
  elif [ -s "$tmp/out" ]; then
    why="stdout not empty: $(head -c 200 "$tmp/out" | head -n 1)"
  elif [ "$lines" -ne 1 ]; then
    why="$lines lines on stderr, expected 1: $(head -c 300 "$tmp/err" | tr '\n' '|')"
  elif ! grep -qF -- "$named" "$tmp/err"; then
    why="stderr does not name $named: $(head -c 300 "$tmp/err")"
  fi
  if [ -z "$why" ]; then
    echo "ok   $name"
    passed=$((passed + 1))
  else
    echo "FAIL $name: $why"
    failed=$((failed + 1))
  fi
done <"$list"

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ] && [ "$passed" -gt 0 ]
