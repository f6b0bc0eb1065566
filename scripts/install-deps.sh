#!/usr/bin/env bash
# Installs what vdbfuse builds and tests with on Debian 12 (run as root or through sudo).
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends \
  build-essential cmake ninja-build ccache pkg-config lld \
  libeigen3-dev libtbb-dev libopenvdb-dev libboost-iostreams-dev \
  libopencv-dev libceres-dev libassimp-dev libzip-dev nlohmann-json3-dev libcli11-dev \
  libmeshoptimizer-dev \
  libpng-dev libdeflate-dev libjpeg62-turbo-dev zlib1g-dev \
  libvtk9-dev xvfb xauth \
  libgtest-dev libbenchmark-dev \
  blender python3-numpy time bc \
  snakemake slurm-wlm munge
# libmeshoptimizer-dev: mesh simplification for textured exports (src/texture/mesh_simplify.cpp).
# libceres-dev: the pose graph of the loop closure (src/slam/pose_graph.cpp).
# blender (3.4 on Debian 12): tests/vdb/blender_test.cpp imports, renders and judges the exports
# headless (it skips, saying so, where blender is missing). python3-numpy: Blender's glTF
# importer and samples/blender/judge_scene.py need it, and Debian's blender does not pull it in.
# snakemake (7.21), slurm-wlm, munge: workflow/ and its tests (tests/workflow); the Slurm test starts
# its own one-node cluster under a temporary folder and skips, saying why, where it cannot.
