#!/usr/bin/env bash
# Configures and builds vdbfuse into ${BUILD_DIR:-build} (Release, Ninja, ccache when present).
# CUDA is built when nvcc is found (/usr/local/cuda); pass -DVDBFUSE_WITH_CUDA=OFF to skip it.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@"
cmake --build "$BUILD_DIR" -j "$(nproc)"
