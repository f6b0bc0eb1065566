#!/usr/bin/env bash
# The figures of textured meshes (issue 38), reproducible:
#   1. dance capture (phone poses, person masked): the full vertex-coloured GLB and the
#      textured GLB of <= 200 k triangles, the export's time, both rendered unlit from one camera
#      in headless Blender (mean colour, mean squared grey gradient), the GLB's import time;
#   2. TUM fr1/xyz (100 frames): the same export, and the simplified surface's distance to the
#      full one (90th percentile, both ways; tests/texture textured_export_test prints it).
#
#   scripts/texture_eval.sh [BUILD_DIR] [OUT_DIR]
#
# BUILD_DIR holds vdbfuse and tests/texture/textured_export_test. Blender (Debian's 3.4) for
# step 1's renders. A few minutes on two cores, most of it fusing the dance at 5.86 mm.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=$(cd "${1:-$here/../build}" && pwd)
out=${2:-/tmp/vdbfuse_texture_eval}
data=${VDBFUSE_DATA_DIR:-$here/../../shared/data}
vdbfuse=$build/src/app/vdbfuse
mkdir -p "$out"

seconds() {  # runs a command, prints its wall time in seconds on stderr
  local t0=$EPOCHREALTIME
  "$@"
  awk -v a="$t0" -v b="$EPOCHREALTIME" -v what="${2:-$1}" 'BEGIN { printf "time: %.1f s (%s)\n", b - a, what }' >&2
}

echo "== dance: fuse (phone poses, person masked)"
"$vdbfuse" reconstruct "$data/record3d_dance_head200.r3d" --poses given \
  --labels "$data/record3d_dance_head200_labels" --dynamic-classes person --device cpu -q -f -o "$out/dance.vdb"
echo "== dance: full vertex-coloured mesh, then the textured export"
seconds "$vdbfuse" mesh "$out/dance.vdb" -o "$out/dance_full.glb" --exclude-classes person -f
seconds "$vdbfuse" mesh "$out/dance.vdb" -o "$out/dance_room.glb" --exclude-classes person --texture \
  --target-triangles 200000 -f
seconds "$vdbfuse" export "$out/dance.vdb" --blender -o "$out/dance_blender" --texture --target-triangles 200000 -f
if command -v blender > /dev/null; then
  echo "== dance: in Blender (File > Import's importer, unlit renders from one camera)"
  blender -b --factory-startup --python "$here/../samples/blender/count_import.py" -- "$out/dance_room.glb" |
    grep '^vdbfuse:'
  blender -b --factory-startup --python "$here/../samples/blender/count_import.py" -- "$out/dance_full.glb" |
    grep '^vdbfuse:'
  blender -b --factory-startup --python "$here/../samples/blender/compare_renders.py" -- \
    "$out/dance_full.glb" "$out/dance_room.glb" --out "$out/renders" --resolution 640x360 --samples 8 |
    grep '^vdbfuse-compare:'
  blender -b --factory-startup --python "$here/../samples/blender/compare_renders.py" -- \
    "$out/dance_full.glb" "$out/dance_room.glb" --out "$out/renders_closer" --resolution 640x360 --samples 8 \
    --zoom 2.5 | grep '^vdbfuse-compare:'
  blender -b --factory-startup --python "$here/../samples/blender/import_scene.py" -- "$out/dance_blender" \
    --render "$out/renders/dance_blender.png" --resolution 640x360 --samples 16 | grep '^vdbfuse: imported'
else
  echo "blender is not installed: no renders"
fi

echo "== TUM fr1/xyz: simplified surface against the full one"
"$build/tests/texture/textured_export_test" --gtest_filter='TexturedTum.*' | grep -E 'TUM fr1|OK|FAILED'
