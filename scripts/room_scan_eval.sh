#!/usr/bin/env bash
# Issue 12, acceptance 1: generates the synthetic room scan (samples/synthetic_room: 8 x 6 x 2.6 m,
# a full turn, Kinect v1 noise) into a temporary folder, reconstructs it with vdbfuse's default
# options, and prints frames/s, peak memory, ATE and the completion of the seen surface against
# the targets: completion >= 95 % within 3 cm, ATE <= 1 cm, peak memory <= 1.5 GB.
# Exit status 0 when all three hold, 1 when one does not, 2 when a step fails.
#
# Usage: scripts/room_scan_eval.sh [BUILD_DIR] [-- EXTRA RECONSTRUCT OPTIONS]
#   FRAMES=300 SEED=1 KEEP=dir (keep the room, scene, mesh and logs there instead of a temp folder)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/eval_common.sh
BUILD_DIR=build
if [ $# -gt 0 ] && [ "$1" != "--" ]; then BUILD_DIR=$1; shift; fi
[ $# -gt 0 ] && [ "$1" == "--" ] && shift
EXTRA=("$@")
FRAMES=${FRAMES:-300}
SEED=${SEED:-1}
VF="$BUILD_DIR/src/app/vdbfuse"
ROOM_TOOL="$BUILD_DIR/samples/synthetic_room/vdbfuse-synth-room"
require_built room_scan_eval "$VF" "$ROOM_TOOL"
[ -x /usr/bin/time ] || { echo "room_scan_eval: /usr/bin/time is missing (apt-get install time)" >&2; exit 2; }

open_output_folder
rm -rf "$OUT/room"  # a kept folder's room from an earlier run

step() { echo; echo "=== $*"; }
fail() { echo "room_scan_eval: $* (logs in $OUT unless it was a temp folder; KEEP=dir keeps them)" >&2; exit 2; }

step "generate: $ROOM_TOOL $OUT/room --frames $FRAMES --seed $SEED"
"$ROOM_TOOL" "$OUT/room" --frames "$FRAMES" --seed "$SEED" || fail "generating the room failed"

step "reconstruct: vdbfuse reconstruct room -o scene.vdb ${EXTRA[*]:-(default options)}"
if ! /usr/bin/time -v -o "$OUT/time.txt" "$VF" reconstruct "$OUT/room" -o "$OUT/scene.vdb" --verbose \
    --trajectory "$OUT/trajectory.txt" -q -f "${EXTRA[@]}" >"$OUT/reconstruct.txt" 2>"$OUT/reconstruct.err"; then
  cat "$OUT/reconstruct.txt" "$OUT/reconstruct.err"
  fail "vdbfuse reconstruct failed"
fi
grep -vE "^\s*$" "$OUT/reconstruct.txt" | grep -vE "^  " | tail -n 12

step "evaluate: vdbfuse evaluate --trajectory trajectory.txt --groundtruth room/groundtruth.txt"
"$VF" evaluate --trajectory "$OUT/trajectory.txt" --groundtruth "$OUT/room/groundtruth.txt" | tee "$OUT/ate.txt" \
  || fail "vdbfuse evaluate failed"

step "mesh: vdbfuse mesh scene.vdb --axes camera -o mesh.ply (the frame of the trajectory)"
"$VF" mesh "$OUT/scene.vdb" --axes camera -o "$OUT/mesh.ply" -f | tail -n 3 || fail "vdbfuse mesh failed"

step "completion: vdbfuse-synth-room --evaluate mesh.ply --trajectory trajectory.txt --frames $FRAMES"
"$ROOM_TOOL" --evaluate "$OUT/mesh.ply" --trajectory "$OUT/trajectory.txt" --frames "$FRAMES" | tee "$OUT/completion.txt" \
  || fail "the completion evaluation failed"

# ---- summary ------------------------------------------------------------------------------------
fps_io=$(sed -nE 's/.*\(([0-9.]+) frames\/s including I\/O\).*/\1/p' "$OUT/reconstruct.txt" | tail -1)
fps_stages=$(sed -nE 's/.*-> ([0-9.]+) frames\/s from the four stages.*/\1/p' "$OUT/reconstruct.txt" | tail -1)
peak_printed=$(sed -nE 's/.*peak memory ([0-9.]+) MiB.*/\1/p' "$OUT/reconstruct.txt" | tail -1)
rss_kib=$(sed -nE 's/.*Maximum resident set size \(kbytes\): ([0-9]+).*/\1/p' "$OUT/time.txt")
tracked=$(grep -E "^tracked " "$OUT/reconstruct.txt" | head -1 | cut -d';' -f1)
ate_cm=$(ate_rmse_cm <"$OUT/ate.txt")
completion=$(sed -nE 's/^completion +([0-9.]+) %.*/\1/p' "$OUT/completion.txt")
accuracy=$(sed -nE 's/^accuracy +(.*)$/\1/p' "$OUT/completion.txt")
rss_mib=$(awk -v k="$rss_kib" 'BEGIN {printf "%.0f", k / 1024}')

verdict=0
check() {  # name value op limit unit
  local ok
  ok=$(awk -v v="$2" -v l="$4" -v op="$3" 'BEGIN {print (op == ">=" ? v >= l : v <= l) ? "pass" : "FAIL"}')
  [ "$ok" == pass ] || verdict=1
  printf "  %-28s %10s %-4s (target %s %s %s)  %s\n" "$1" "$2" "$5" "$3" "$4" "$5" "$ok"
}
step "summary ($FRAMES frames, seed $SEED${EXTRA[*]:+, options: ${EXTRA[*]}})"
echo "  $tracked"
printf "  %-28s %10s frames/s (including I/O); %s frames/s from the four stages' medians\n" "speed" "$fps_io" "$fps_stages"
printf "  %-28s %10s MiB (printed by reconstruct)\n" "peak memory" "$peak_printed"
printf "  %-28s %10s\n" "accuracy" "$accuracy"
check "completion within 3 cm" "$completion" ">=" 95 "%"
check "ATE (rmse)" "$ate_cm" "<=" 1.0 "cm"
check "peak memory (max RSS)" "$rss_mib" "<=" 1536 "MiB"
exit $verdict
