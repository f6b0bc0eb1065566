#!/usr/bin/env bash
# run_reconstruct.sh VDBFUSE CAPTURE_DIR INPUT [RECONSTRUCT OPTIONS...]
# One capture's reconstruct job: writes CAPTURE_DIR/scene.vdb, trajectory.txt and reconstruct.json
# (the run's figures), with checkpoints. A job killed part way (the node died, the scheduler's
# time limit, a SIGKILL) leaves CAPTURE_DIR/scene.vdb.checkpoint behind, which Snakemake does not
# know about and so keeps; the next attempt continues from it to the same scene. A checkpoint
# that cannot be resumed (the options changed since) is said so in the log, and the run starts over.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
vdbfuse=$1 dir=$2 input=$3
shift 3
run() {
  "$here/timed.sh" "$dir/usage/reconstruct.json" "$vdbfuse" reconstruct "$input" -o "$dir/scene.vdb" \
    --trajectory "$dir/trajectory.txt" --report-json "$dir/reconstruct.json" -q "$@"
}
if [ -f "$dir/scene.vdb.checkpoint" ]; then
  echo "vdbfuse workflow: resuming from $dir/scene.vdb.checkpoint"
  run "$@" --resume
  status=$?
  # 1 is vdbfuse's error status; a signal (the job killed again) keeps the checkpoint for next time.
  if [ "$status" -ne 1 ]; then exit "$status"; fi
  echo "vdbfuse workflow: the checkpoint could not be resumed (above); starting over"
fi
run "$@" --force
