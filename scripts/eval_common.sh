# Sourced by the evaluation scripts (room_scan_eval.sh, corridor_scan_eval.sh, tracking_judge.sh):
# the set-up they share. Each names itself in its messages.

# require_built SCRIPT BINARY...: exits 2, saying which target to build, when a binary is missing
# (BUILD_DIR is the build folder the script was given).
require_built() {
  local script=$1 bin
  shift
  for bin in "$@"; do
    [ -x "$bin" ] || { echo "$script: $bin is missing; build it: ninja -C $BUILD_DIR vdbfuse vdbfuse-synth-room" >&2; exit 2; }
  done
}

# Sets OUT: the folder KEEP names (made if need be), else a temp folder removed on exit.
open_output_folder() {
  if [ -n "${KEEP:-}" ]; then
    OUT=$KEEP
    mkdir -p "$OUT"
  else
    OUT=$(mktemp -d)
    trap 'rm -rf "$OUT"' EXIT
  fi
}

# ate_rmse_cm: the ATE's rmse (cm) from `vdbfuse evaluate` output on stdin.
ate_rmse_cm() {
  awk '/^ATE/ {a=1} a && $1=="rmse" {print $2; exit}'
}
