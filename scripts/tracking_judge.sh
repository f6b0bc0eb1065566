#!/usr/bin/env bash
# The set a tracking change is judged on (README "Judging a tracking change"): the synthetic ring
# corridor (samples/synthetic_room --scene corridor: a 38 m walk with Kinect v1 depth, 1200
# frames) at 640x480 and 320x240, three walks each (--walk 0, 1, 2: the same loop, the camera
# carried differently, so that the hard views come at other moments), and the real samples with
# ground truth in ../shared/data (TUM fr1/xyz 100 frames, fr3/teddy 60, 7-Scenes redkitchen 100
# and 500).
# A change to the motion prior or the tracker's checks can win on one walk and lose another, or
# at the other resolution, while the short real samples barely move (the camera-centre hold,
# 2026-12-06, against the points' mean held before, on walk 0: 640x480 5.9 -> 1.5 cm, 320x240
# 7.5 -> 84; on walk 1: 77.5 -> 3.2 and 96.5 -> 24.5): the table shows all of them at once.
# Per case: frames tracked and lost, loops found and holding, ATE of the written (loop-closed)
# trajectory and of the first pass (--odometry: tracking before the loops moved it), and the wall time;
# then per size the corridors' median and worst ATE and how many are within 5 cm (issue 36's
# target). One corridor run is a draw: a last-bit change in code generation grows along the
# corridor's weakly measured directions into a different run (walk 0 at 640x480 gave 1.5 or 33.8
# cm with builds that differ in no line it executes), so SEEDS="1 2 3" shows the spread.
# Exit status 0 when every run finished (whatever its figures), 2 when a step failed.
#
# Usage: scripts/tracking_judge.sh [BUILD_DIR]
#   SIZES="640x480 320x240" WALKS="0 1 2" SEEDS="1": the corridors, every combination (the seed
#   is the sensor noise's; SIZES= leaves them out); DEPTH_MODELS="kinect-v1 tum" adds the same
#   walks without the Kinect's disparity steps and per-pixel bias (tracked to about 2 cm, where a
#   wrong loop shows: README "Measured");
#   STARTS="0 340" adds the same walks started later (--gap 0:340: a new origin, a model without
#   the first frames; from 200, 340 or 500 walk 0 slides 60-107 cm at its last corner, README
#   "Beyond the judge"; names get _from340);
#   REAL=0 leaves out the real samples; DATA=../shared/data where they are;
#   RECONSTRUCT="..." adds options to every reconstruction;
#   KEEP=dir keeps corridors, trajectories and logs there, each run's per-frame tracking log too
#   (runs/CASE/frames.csv, README "Reading a run's frame log"; a second run with the same KEEP
#   reuses the corridors it generated), else a temp folder.
# Time on two cores: about 1.5-2.5 min a 320x240 corridor, 2.5-3.5 min a 640x480 one, 1 min the real four.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/eval_common.sh
BUILD_DIR=${1:-build}
SIZES=${SIZES-640x480 320x240}
WALKS=${WALKS-0 1 2}
SEEDS=${SEEDS-1}
DEPTH_MODELS=${DEPTH_MODELS-kinect-v1}
STARTS=${STARTS-0}
DATA=${DATA:-../shared/data}
read -r -a EXTRA <<< "${RECONSTRUCT:-}"
VF="$BUILD_DIR/src/app/vdbfuse"
SYNTH="$BUILD_DIR/samples/synthetic_room/vdbfuse-synth-room"
require_built tracking_judge "$VF" "$SYNTH"
open_output_folder
fail() {
  if [ -n "${KEEP:-}" ]; then echo "tracking_judge: $* (logs in $OUT)" >&2; else echo "tracking_judge: $* (KEEP=dir keeps the logs)" >&2; fi
  exit 2
}

ate() {  # ate TRAJECTORY GROUNDTRUTH: the ATE's rmse in cm, or "-" without a trajectory
  [ -s "$1" ] || { echo "-"; return; }
  "$VF" evaluate --trajectory "$1" --groundtruth "$2" | ate_rmse_cm
}

ROWS=()
declare -A CORRIDOR_ATES  # per size, the written trajectories' ATEs
judge() {  # judge NAME INPUT GROUNDTRUTH [reconstruct options]
  local name=$1 input=$2 truth=$3; shift 3
  local run="$OUT/runs/$name"
  mkdir -p "$run"
  echo "=== $name: vdbfuse reconstruct $input $* ${EXTRA[*]:-}"
  local start=$SECONDS
  if ! "$VF" reconstruct "$input" -o "$run/scene.vdb" --trajectory "$run/trajectory.txt" \
      --odometry "$run/odometry.txt" --report-json "$run/report.json" --frame-log "$run/frames.csv" \
      -q -f "$@" "${EXTRA[@]}" \
      >"$run/reconstruct.txt" 2>&1; then
    tail -n 20 "$run/reconstruct.txt"
    fail "vdbfuse reconstruct ($name) failed"
  fi
  local seconds=$((SECONDS - start))
  local tracked lost loops
  tracked=$(sed -nE 's/.*"tracked": ([0-9]+).*/\1/p' "$run/report.json")
  lost=$(sed -nE 's/.*"lost": ([0-9]+).*/\1/p' "$run/report.json")
  # "loop closure: 123 keyframes, 358 candidate pairs checked, 22 loops found, 21 hold (1 rejected)..."
  loops=$(sed -nE 's/^loop closure: .* ([0-9]+) loops found, ([0-9]+) hold.*/\2 of \1/p' "$run/reconstruct.txt" | tail -n 1)
  local written first
  written=$(ate "$run/trajectory.txt" "$truth") || fail "vdbfuse evaluate ($name) failed"
  first=$(ate "$run/odometry.txt" "$truth") || fail "vdbfuse evaluate ($name, first pass) failed"
  LAST_ATE=$written
  ROWS+=("$(printf "%-42s %8s %6s %9s %9s %13s %6s" "$name" "$tracked" "$lost" "${loops:--}" "$written" "$first" "$seconds")")
  echo "${ROWS[-1]}"
}

for model in $DEPTH_MODELS; do
  # The Kinect v1 model's corridors keep their names (and a KEEP folder's corridors); others add theirs.
  suffix="" label=""
  [ "$model" != kinect-v1 ] && suffix="_$model" label=" $model depth"
  for size in $SIZES; do
    for walk in $WALKS; do
      for seed in $SEEDS; do
        for start in $STARTS; do
          # A later start leaves the walk's first frames out (--gap 0:START): a new origin and a
          # model without them.
          start_suffix="" start_label="" start_options=()
          [ "$start" != 0 ] && start_suffix="_from$start" start_label=" from $start" start_options=(--gap "0:$start")
          name="corridor_${size}_walk${walk}_seed$seed$suffix$start_suffix"
          corridor="$OUT/$name"
          if [ ! -s "$corridor/groundtruth.txt" ]; then
            echo "=== generate: $SYNTH $corridor --scene corridor --size $size --walk $walk --seed $seed --depth-model $model ${start_options[*]:-}"
            "$SYNTH" "$corridor" --scene corridor --size "$size" --walk "$walk" --seed "$seed" --depth-model "$model" \
              "${start_options[@]}" -f >"$OUT/generate_$name.txt" 2>&1 \
              || { cat "$OUT/generate_$name.txt"; fail "generating the corridor ($size, walk $walk, seed $seed, $model, start $start) failed"; }
          fi
          judge "corridor $size walk $walk seed $seed$label$start_label" "$corridor" "$corridor/groundtruth.txt"
          CORRIDOR_ATES[$size]="${CORRIDOR_ATES[$size]:-} $LAST_ATE"
        done
      done
    done
  done
done

if [ "${REAL:-1}" != 0 ]; then
  for sample in tum_fr1_xyz_head100 tum_fr3_teddy_head60 7scenes_redkitchen_head100 7scenes_redkitchen_head500; do
    [ -d "$DATA/$sample" ] || fail "$DATA/$sample is missing (the shared data; DATA=dir names another place)"
    judge "$sample" "$DATA/$sample" "$DATA/$sample"
  done
fi

echo
echo "=== tracking judge (${EXTRA[*]:-default options}; $BUILD_DIR)"
printf "%-42s %8s %6s %9s %9s %13s %6s\n" case tracked lost "loops" "ATE cm" "first pass cm" "s"
printf "%s\n" "${ROWS[@]}"
# One corridor run is a draw (README "Judging a tracking change"): per size, how the runs spread
# (a run without a trajectory counts as the worst).
for size in $SIZES; do
  printf "%s\n" ${CORRIDOR_ATES[$size]:-} | sed 's/^-$/inf/' | sort -g | awk -v size="$size" '
    { n++; a[n] = $1; within += ($1 != "inf" && $1 <= 5) }
    END {
      if (!n) exit
      median = (n % 2) ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2
      printf "corridor %s: median ATE %s cm, worst %s, %d of %d runs <= 5 cm\n", size, median, a[n], within, n
    }'
done
