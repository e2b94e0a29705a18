#!/usr/bin/env bash
# gather sim --video through the CLI as built: the encoder is the module
# libgather_video.so, loaded only for --video (docs/simulator.md). A plan of
# maps/office (PAP, one collector), one seed of one cycle, written as .avi
# (Motion JPEG) and .mp4: each a non-empty file of its container; `gather`
# itself links neither OpenCV's video I/O nor its image codecs.
#
#   tests/cli/video.sh PATH/TO/gather
set -u
G=${1:?usage: $0 PATH/TO/gather}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
office="$here/../../maps/office.scenario.yaml"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
if ldd "$G" | grep -qE 'libopencv_(videoio|imgcodecs)'; then
  echo "FAIL gather links OpenCV's videoio or imgcodecs (the video encoder is a module, PNGs go through libpng)"
  fail=1
else
  echo "ok   gather links neither videoio nor imgcodecs"
fi
if ! "$G" plan "$office" --config pap:1 --out "$tmp/plan" > "$tmp/plan.log" 2>&1; then
  echo "FAIL gather plan: $(tail -c 300 "$tmp/plan.log")"
  exit 1
fi
for ext in avi mp4; do
  if ! "$G" sim "$tmp/plan" --seeds 1 --cycles 1 --out "$tmp/sim_$ext" --video "$tmp/mission.$ext" > "$tmp/sim.log" 2>&1; then
    echo "FAIL gather sim --video mission.$ext: $(tail -c 300 "$tmp/sim.log")"
    fail=1
    continue
  fi
  magic=$(head -c 12 "$tmp/mission.$ext" | tr -d '\0' | tr -c '[:print:]' '.')
  case $ext in
    avi) want=RIFF ;;
    mp4) want=ftyp ;;
  esac
  if [ -s "$tmp/mission.$ext" ] && [[ $magic == *"$want"* ]]; then
    echo "ok   gather sim --video mission.$ext ($(stat -c %s "$tmp/mission.$ext") bytes)"
  else
    echo "FAIL gather sim --video mission.$ext: no $want header ($magic)"
    fail=1
  fi
done
exit $fail
