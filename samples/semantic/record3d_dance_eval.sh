#!/usr/bin/env bash
# The Record3D figures of semantic fusion, reproducible: ATE of --poses icp against the phone's
# (ARKit) poses, and how much of the dancer --dynamic-classes person removes.
#
#   samples/semantic/record3d_dance_eval.sh [BUILD_DIR] [OUT_DIR]
#
# BUILD_DIR must hold vdbfuse and tests/semantic/person_removal_eval (ninja vdbfuse person_removal_eval).
# Voxels of 1 cm in the sparse volume (no box: bricks where the depth reaches), CPU backend.
# About 2 minutes on 2 cores.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-$here/../../build}
out=${2:-/tmp/vdbfuse_dance_eval}
data=${VDBFUSE_DATA_DIR:-$here/../../../shared/data}
capture=$data/record3d_dance_head200.r3d
labels=$data/record3d_dance_head200_labels
volume=(--voxel-size-m 0.01 --device cpu -q -f)
mkdir -p "$out"

# 1. ICP tracking with the person masked out of ICP and TSDF, against the phone's (ARKit) poses,
#    which `evaluate` reads from the capture itself (ATE aligns the two rigidly).
"$build/src/app/vdbfuse" reconstruct "$capture" --poses icp --labels "$labels" --dynamic-classes person \
  "${volume[@]}" -o "$out/icp_person_masked.vdb" --trajectory "$out/icp_person_masked.txt"
"$build/src/app/vdbfuse" evaluate -t "$out/icp_person_masked.txt" -g "$capture"

# 2. Person removal: the same capture with the phone's poses, with and without the option.
"$build/src/app/vdbfuse" reconstruct "$capture" --poses given --labels "$labels" --dynamic-classes person \
  "${volume[@]}" -o "$out/given_person_masked.vdb"
"$build/src/app/vdbfuse" reconstruct "$capture" --poses given --labels "$labels" \
  "${volume[@]}" -o "$out/given_plain.vdb"
"$build/tests/semantic/person_removal_eval" "$capture" "$labels" "$out/given_person_masked.vdb" "$out/given_plain.vdb"
