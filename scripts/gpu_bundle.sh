#!/usr/bin/env bash
# Builds the GPU check bundle into DIR: everything a GPU check of vdbfuse needs on a bare x86-64
# Linux with an NVIDIA driver, in at most 48 MiB (cuda/README.md, "The GPU bundle"):
#   bin/   cuda_memory_test, cuda_parity_test, fusion_bench (sm_90, stripped; libpng, libdeflate, libjpeg and
#          zlib linked in; rpath $ORIGIN/../lib)
#   lib/   the shared libraries they load beyond glibc (TBB, libstdc++, libgcc_s); the CUDA driver
#          comes from the machine, the CUDA runtime is linked in
#   glibc/ the builder's glibc, which run.sh uses where the machine's is older than the programs need
#   data/  compact copies of the shared TUM captures (tests/cuda/bundle_frames.cpp)
#   run.sh the check itself (scripts/gpu_bundle_run.sh), MANIFEST what was built from what
#
#   bash scripts/gpu_bundle.sh DIR
#
# Builds in its own folder (GPU_BUNDLE_BUILD_DIR, default build-gpu-bundle; ccache makes a rebuild
# cheap), writes DIR.partial beside DIR and renames it, and ends by checking the size and that
# every program resolves its libraries from the bundle and glibc alone (check_gpu_bundle.sh).
set -euo pipefail
if [ $# -ne 1 ]; then
  echo "usage: bash scripts/gpu_bundle.sh DIR" >&2
  exit 2
fi
ROOT=$(cd "$(dirname "$0")/.." && pwd)
DIR=$(realpath -m "$1")
BUILD=${GPU_BUNDLE_BUILD_DIR:-$ROOT/build-gpu-bundle}
DATA=${VDBFUSE_DATA_DIR:-$ROOT/../shared/data}
NVCC=${CUDACXX:-/usr/local/cuda/bin/nvcc}
CAPTURES="tum_fr1_xyz_head100 tum_fr3_teddy_head60"

[ -x "$NVCC" ] || { echo "gpu_bundle: no CUDA compiler at $NVCC (install the CUDA toolkit or set CUDACXX)" >&2; exit 1; }
for capture in $CAPTURES; do
  [ -d "$DATA/$capture" ] || { echo "gpu_bundle: capture not found: $DATA/$capture (the shared data must sit beside the project as ../shared/data)" >&2; exit 1; }
done
if [ -e "$DIR" ] && [ ! -f "$DIR/MANIFEST" ] && [ -n "$(ls -A "$DIR")" ]; then
  echo "gpu_bundle: $DIR exists and is not a GPU bundle; give a new or empty folder" >&2
  exit 1
fi

# RPATH (not RUNPATH): it also serves libtbb's own dependency on libstdc++.
mkdir -p "$BUILD"
cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CUDA_COMPILER="$NVCC" \
  -DVDBFUSE_WITH_CUDA=ON -DCMAKE_CUDA_ARCHITECTURES=90 -DVDBFUSE_WITH_VIEWER=OFF \
  -DVDBFUSE_STATIC_IMAGE_CODECS=ON -DVDBFUSE_DATA_DIR="$DATA" \
  -DCMAKE_BUILD_RPATH='$ORIGIN/../lib' -DCMAKE_EXE_LINKER_FLAGS='-Wl,--disable-new-dtags' >"$BUILD/configure.log" 2>&1 ||
  { cat "$BUILD/configure.log" >&2; exit 1; }
ninja -C "$BUILD" cuda_memory_test cuda_parity_test fusion_bench bundle_frames

STAGE="$DIR.partial"
rm -rf "$STAGE"
mkdir -p "$STAGE/bin" "$STAGE/lib" "$STAGE/data"
for program in cuda_memory_test cuda_parity_test fusion_bench; do
  cp "$BUILD/tests/cuda/$program" "$STAGE/bin/"
  strip --strip-unneeded "$STAGE/bin/$program"
done

# Shared libraries beyond glibc (and the CUDA driver, which the runtime opens from the machine).
is_system_lib() {
  case "$1" in
    linux-vdso.so.*|ld-linux-x86-64.so.*|libc.so.*|libm.so.*|libpthread.so.*|libdl.so.*|librt.so.*|libresolv.so.*|libutil.so.*|libcuda.so.*) return 0 ;;
  esac
  return 1
}
for program in "$STAGE"/bin/*; do
  ldd "$program" | awk '$2 == "=>" && $3 ~ /^\// {print $1, $3}' | while read -r name path; do
    is_system_lib "$name" || [ -e "$STAGE/lib/$name" ] || cp -L "$path" "$STAGE/lib/$name"
  done
done
# libtbb opens its allocator from its own folder when it is there (else it uses malloc).
TBB_DIR=$(dirname "$(ldd "$BUILD/tests/cuda/fusion_bench" | awk '$1 ~ /^libtbb\.so/ {print $3}')")
[ -f "$TBB_DIR/libtbbmalloc.so.2" ] && cp -L "$TBB_DIR/libtbbmalloc.so.2" "$STAGE/lib/"
strip --strip-unneeded "$STAGE"/lib/*.so*

# glibc itself, kept apart in glibc/: run.sh starts the programs through this loader where the
# machine's glibc is older than the one they were built against (Ubuntu 22.04 has 2.35, Debian 12
# builds need 2.36). Never in lib/: a libc without its own loader would break every program.
mkdir -p "$STAGE/glibc"
for name in ld-linux-x86-64.so.2 libc.so.6 libm.so.6 libpthread.so.0 libdl.so.2 librt.so.1; do
  path=$(ldconfig -p | awk -v n="$name" '$1 == n && /x86-64/ && !found {print $NF; found = 1}')
  [ -n "$path" ] || { echo "gpu_bundle: glibc's $name not found" >&2; exit 1; }
  cp -L "$path" "$STAGE/glibc/$name"
done

for capture in $CAPTURES; do
  "$BUILD/tests/cuda/bundle_frames" "$DATA/$capture" "$STAGE/data/$capture"
done
cp "$ROOT/scripts/gpu_bundle_run.sh" "$STAGE/run.sh"
chmod +x "$STAGE/run.sh"

# The newest glibc symbol version the programs need: run.sh refuses an older glibc by name.
GLIBC_NEEDED=$(for f in "$STAGE"/bin/* "$STAGE"/lib/*; do objdump -T "$f"; done | grep -o 'GLIBC_[0-9.]*' |
  sed 's/GLIBC_//' | sort -t. -k1,1n -k2,2n -k3,3n | tail -1)
{
  echo "vdbfuse GPU bundle"
  echo "commit $(git -C "$ROOT" describe --always --dirty 2>/dev/null || echo unknown)"
  echo "built $(date -u +%Y-%m-%dT%H:%M:%SZ) on $(uname -m), CUDA $("$NVCC" --version | sed -n 's/.*release \([0-9.]*\).*/\1/p') for sm_90"
  echo "glibc_needed $GLIBC_NEEDED"
  echo "captures $CAPTURES"
} >"$STAGE/MANIFEST"

rm -rf "$DIR"
mv "$STAGE" "$DIR"
bash "$ROOT/scripts/check_gpu_bundle.sh" --no-run "$DIR"
