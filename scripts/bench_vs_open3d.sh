#!/usr/bin/env bash
# Runs vdbfuse (--bench: frames decoded first, four fusion stages timed) and the Open3D 0.16 dense
# SLAM peer (../shared/peers/open3d_slam, needs Debian's libopen3d-dev) on the same TUM folders in
# one run, and prints frames/s, per-stage times, peak memory and ATE for both.
# Usage: scripts/bench_vs_open3d.sh [BUILD_DIR] [TUM_FOLDER...]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
shift || true
DATA=${VDBFUSE_DATA_DIR:-../shared/data}
SEQUENCES=("$@")
[ ${#SEQUENCES[@]} -gt 0 ] || SEQUENCES=("$DATA/tum_fr1_xyz_head100" "$DATA/tum_fr3_teddy_head60")
VF="$BUILD_DIR/src/app/vdbfuse"
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT

PEER=""
if [ -f /usr/include/open3d/Open3D.h ] || dpkg -s libopen3d-dev >/dev/null 2>&1; then
  cmake -S ../shared/peers/open3d_slam -B "$OUT/o3d_build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$OUT/o3d_build" -j "$(nproc)" >/dev/null
  PEER="$OUT/o3d_build/open3d_dense_slam"
else
  echo "libopen3d-dev is not installed: running vdbfuse alone (apt-get install libopen3d-dev for the peer)"
fi

for seq in "${SEQUENCES[@]}"; do
  name=$(basename "$seq")
  echo "=== $name"
  "$VF" reconstruct "$seq" --bench -q -f --trajectory "$OUT/$name.vdbfuse.txt" | grep -E "^(measure|track|integrate|raycast|fusion) |frames in"
  echo -n "vdbfuse ATE: "
  "$VF" evaluate --trajectory "$OUT/$name.vdbfuse.txt" --groundtruth "$seq/groundtruth.txt" | grep -A1 "^ATE" | tail -1
  if [ -n "$PEER" ]; then
    /usr/bin/time -f "open3d peak memory %M KiB" "$PEER" --dataset "$seq" --out "$OUT/o3d_$name" >/dev/null 2>"$OUT/o3d_$name.err" || {
      cat "$OUT/o3d_$name.err"; continue; }
    grep SUMMARY "$OUT/o3d_$name/summary.txt"
    grep "peak memory" "$OUT/o3d_$name.err"
    echo -n "open3d ATE: "
    "$VF" evaluate --trajectory "$OUT/o3d_$name/trajectory.txt" --groundtruth "$seq/groundtruth.txt" | grep -A1 "^ATE" | tail -1
  fi
done
