#!/usr/bin/env bash
# Issue 36, acceptance 1 (and issue 41's stress cases): generates the synthetic ring corridor
# (samples/synthetic_room, --scene corridor: a 38 m walk 1.17 times round a 32 m loop, weakly
# textured walls, Kinect v1 depth) into a folder, reconstructs it twice with vdbfuse, with its
# default tracking and with the true poses (--poses given), and prints for both: frames tracked,
# ATE, completion of the seen surface within 3 cm, accuracy (mean, median, 90th percentile) and
# time, against issue 36's targets: ATE <= 5 cm and at most a tenth of the first pass's (the
# tracking before the loops moved it), completion >= 95 %, and the 90th percentile
# within 0.5 cm of the run with the true poses (no doubled walls).
# Exit status 0 when the default run meets all four, 1 when it does not, 2 when a step fails.
#
# Usage: scripts/corridor_scan_eval.sh [BUILD_DIR] [-- SCAN OPTIONS]
#   SCAN OPTIONS go to the generator and to the evaluator alike, e.g. -- --gap 600:45,
#   -- --blank 300:30, -- --close-wall 510:150, -- --frames 600.
#   KEEP=dir keeps the corridor, scenes, meshes and logs there (else a temp folder);
#   RECONSTRUCT="..." adds options to both reconstructions; SKIP_GIVEN=1 leaves out the true-pose run.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/eval_common.sh
BUILD_DIR=build
if [ $# -gt 0 ] && [ "$1" != "--" ]; then BUILD_DIR=$1; shift; fi
[ $# -gt 0 ] && [ "$1" == "--" ] && shift
SCAN=(--scene corridor "$@")
read -r -a EXTRA <<< "${RECONSTRUCT:-}"
VF="$BUILD_DIR/src/app/vdbfuse"
SYNTH="$BUILD_DIR/samples/synthetic_room/vdbfuse-synth-room"
require_built corridor_scan_eval "$VF" "$SYNTH"
[ -x /usr/bin/time ] || { echo "corridor_scan_eval: /usr/bin/time is missing (apt-get install time)" >&2; exit 2; }

open_output_folder
step() { echo; echo "=== $*"; }
fail() { echo "corridor_scan_eval: $* (logs in $OUT unless it was a temp folder; KEEP=dir keeps them)" >&2; exit 2; }

step "generate: $SYNTH $OUT/corridor ${SCAN[*]} -f"
/usr/bin/time -f "%e s wall, %U s user, %M KiB max RSS" -o "$OUT/generate_time.txt" \
  "$SYNTH" "$OUT/corridor" "${SCAN[@]}" -f | tee "$OUT/generate.txt" || fail "generating the corridor failed"
echo "generator: $(cat "$OUT/generate_time.txt")"

run() {  # run NAME [reconstruct options]
  local name=$1; shift
  step "$name: vdbfuse reconstruct corridor -o $name.vdb $* ${EXTRA[*]:-}"
  if ! /usr/bin/time -f "%e" -o "$OUT/$name.time" "$VF" reconstruct "$OUT/corridor" -o "$OUT/$name.vdb" \
      --trajectory "$OUT/$name.txt" -q -f "$@" "${EXTRA[@]}" >"$OUT/$name.reconstruct.txt" 2>"$OUT/$name.reconstruct.err"; then
    cat "$OUT/$name.reconstruct.txt" "$OUT/$name.reconstruct.err"
    fail "vdbfuse reconstruct ($name) failed"
  fi
  grep -vE "^\s*$" "$OUT/$name.reconstruct.txt" | grep -vE "^  " | tail -n 8
  "$VF" evaluate --trajectory "$OUT/$name.txt" --groundtruth "$OUT/corridor/groundtruth.txt" | tee "$OUT/$name.ate.txt" \
    || fail "vdbfuse evaluate ($name) failed"
  "$VF" mesh "$OUT/$name.vdb" --axes camera -o "$OUT/$name.ply" -f | tail -n 2 || fail "vdbfuse mesh ($name) failed"
  "$SYNTH" --evaluate "$OUT/$name.ply" --trajectory "$OUT/$name.txt" "${SCAN[@]}" | tee "$OUT/$name.eval.txt" \
    || fail "the surface evaluation ($name) failed"
}
run default --odometry "$OUT/default.odometry.txt"
# The first pass's trajectory (--odometry): issue 36 wants the default run's ATE at most a tenth
# of the run without loop closure. A run with --loop-closure off tracks the same frames the same
# way but where the walk comes back: without the loops to join the visits it does not restart the
# old bricks (fusion/params.h restart_stale_bricks; walk 0 at 640x480, 2026-12-07: first pass
# 7.8 cm, --loop-closure off 8.1).
if [ -s "$OUT/default.odometry.txt" ]; then
  "$VF" evaluate --trajectory "$OUT/default.odometry.txt" --groundtruth "$OUT/corridor/groundtruth.txt" \
    >"$OUT/odometry.ate.txt" || fail "vdbfuse evaluate (odometry) failed"
fi
[ -n "${SKIP_GIVEN:-}" ] || run given --poses given

# ---- summary ------------------------------------------------------------------------------------
field() {  # field NAME WHAT
  case $2 in
    tracked) grep -E "^tracked " "$OUT/$1.reconstruct.txt" | head -1 | cut -d';' -f1 ;;
    ate) ate_rmse_cm 2>/dev/null <"$OUT/$1.ate.txt" ;;
    completion) sed -nE 's/^completion +([0-9.]+) %.*/\1/p' "$OUT/$1.eval.txt" ;;
    mean) sed -nE 's/^accuracy +mean ([0-9.]+) mm.*/\1/p' "$OUT/$1.eval.txt" ;;
    median) sed -nE 's/^accuracy .*median ([0-9.]+) mm.*/\1/p' "$OUT/$1.eval.txt" ;;
    p90) sed -nE 's/^accuracy .*90th percentile ([0-9.]+) mm.*/\1/p' "$OUT/$1.eval.txt" ;;
    time) cat "$OUT/$1.time" ;;
  esac
}
step "summary (${SCAN[*]}${EXTRA[*]:+; reconstruct: ${EXTRA[*]}})"
printf "  %-8s %-34s %9s %12s %9s %9s %9s %8s\n" run tracked "ATE cm" "complete %" "mean mm" "median mm" "p90 mm" "time s"
names=(default)
[ -n "${SKIP_GIVEN:-}" ] || names+=(given)
for n in "${names[@]}"; do
  printf "  %-8s %-34s %9s %12s %9s %9s %9s %8s\n" "$n" "$(field "$n" tracked)" "$(field "$n" ate)" \
    "$(field "$n" completion)" "$(field "$n" mean)" "$(field "$n" median)" "$(field "$n" p90)" "$(field "$n" time)"
done

verdict=0
check() {  # name value op limit unit
  local ok
  ok=$(awk -v v="$2" -v l="$4" -v op="$3" 'BEGIN {print (op == ">=" ? v >= l : v <= l) ? "pass" : "FAIL"}')
  [ "$ok" == pass ] || verdict=1
  printf "  %-40s %10s %-3s (target %s %s %s)  %s\n" "$1" "$2" "$5" "$3" "$4" "$5" "$ok"
}
echo
check "ATE (rmse), default options" "$(field default ate)" "<=" 5.0 "cm"
odometry_ate=$(field odometry ate)
if [ -n "$odometry_ate" ]; then
  check "ATE <= a tenth of the first pass's" "$(field default ate)" "<=" \
    "$(awk -v o="$odometry_ate" 'BEGIN {printf "%.3f", o / 10}')" "cm"
  echo "  (first pass, the tracking before the loops moved it: ATE $odometry_ate cm)"
fi
check "completion within 3 cm, default options" "$(field default completion)" ">=" 95 "%"
if [ -z "${SKIP_GIVEN:-}" ]; then
  limit=$(awk -v g="$(field given p90)" 'BEGIN {printf "%.2f", g + 5}')
  check "90th percentile (given + 5 mm)" "$(field default p90)" "<=" "$limit" "mm"
fi
exit $verdict
