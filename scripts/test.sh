#!/usr/bin/env bash
# Installs the dependencies, builds everything (CUDA too when nvcc exists) and runs every test.
# Tests read real captures from ../shared/data; GPU tests skip with a message where no GPU exists.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
BUILD_DIR=${BUILD_DIR:-build} bash scripts/build.sh
# The GPU bundle (cuda/README.md) is built and checked without a GPU so that it never rots:
# size, library resolution, and run.sh's no-GPU path under a bare environment.
if [ -x "${CUDACXX:-/usr/local/cuda/bin/nvcc}" ]; then
  bundle_parent=$(mktemp -d)
  bash scripts/gpu_bundle.sh "$bundle_parent/gpu"
  bash scripts/check_gpu_bundle.sh "$bundle_parent/gpu"
  rm -rf "$bundle_parent"
else
  echo "GPU bundle: skipped, no CUDA compiler (${CUDACXX:-/usr/local/cuda/bin/nvcc})"
fi
ctest --test-dir "${BUILD_DIR:-build}" --output-on-failure -j 2
