#!/usr/bin/env bash
# An agent that hears nothing from the OC stops after --silence seconds
# with exit status 1, and its last line names the URL and the likely cause.
# memq:// (in-process LCM) keeps it off every network.
#
#   tests/cli/agent_silence.sh GATHER GATHER_AGENT
set -u
gather=${1:?usage: $0 GATHER GATHER_AGENT}
agent=${2:?usage: $0 GATHER GATHER_AGENT}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$gather" plan "$here/../../maps/office.scenario.yaml" --config pap:0 --out "$tmp/plan" >/dev/null 2>"$tmp/plan.err" ||
  { echo "FAIL: gather plan: $(cat "$tmp/plan.err")"; exit 1; }
timeout 20 "$agent" --id 0 --plan "$tmp/plan" --insecure --lcm-url memq:// --silence 1 >/dev/null 2>"$tmp/err"
rc=$?
last=$(tail -n 1 "$tmp/err")
want="gather_agent 0: nothing heard from the OC for 1 s on memq://: is the OC running on this URL?"
if [ "$rc" -ne 1 ] || [ "$last" != "$want" ]; then
  echo "FAIL agent silence: exit $rc (want 1), last line '$last' (want '$want')"
  exit 1
fi
echo "ok   agent silence: $last"
