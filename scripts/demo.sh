#!/usr/bin/env bash
# Installs the dependencies, builds, and reconstructs the shared TUM sample:
# scene, trajectory, colored mesh and the trajectory error against the motion-capture ground truth.
set -euo pipefail
cd "$(dirname "$0")/.."
DATA=${VDBFUSE_DATA_DIR:-../shared/data}
OUT=${OUT_DIR:-out}
bash scripts/install-deps.sh
bash scripts/build.sh
mkdir -p "$OUT"
rm -f "$OUT"/fr1_xyz.vdb "$OUT"/fr1_xyz.txt "$OUT"/fr1_xyz.ply
VF=build/src/app/vdbfuse
$VF reconstruct "$DATA/tum_fr1_xyz_head100" -o "$OUT/fr1_xyz.vdb" --trajectory "$OUT/fr1_xyz.txt"
$VF evaluate --trajectory "$OUT/fr1_xyz.txt" --groundtruth "$DATA/tum_fr1_xyz_head100/groundtruth.txt"
$VF mesh "$OUT/fr1_xyz.vdb" -o "$OUT/fr1_xyz.ply"
$VF info "$OUT/fr1_xyz.vdb"
echo "wrote $OUT/fr1_xyz.vdb, $OUT/fr1_xyz.ply and $OUT/fr1_xyz.txt"
