#!/usr/bin/env bash
# Installs the dependencies, builds everything (CUDA too when nvcc exists) and runs every test.
# Tests read real captures from ../shared/data; GPU tests skip with a message where no GPU exists.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
BUILD_DIR=${BUILD_DIR:-build} bash scripts/build.sh
ctest --test-dir "${BUILD_DIR:-build}" --output-on-failure -j 2
