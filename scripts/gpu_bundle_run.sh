#!/usr/bin/env bash
# The GPU check of vdbfuse, run from a bundle made by scripts/gpu_bundle.sh (copied there as
# run.sh). Needs nothing but bash, coreutils, glibc and an NVIDIA driver; works under
# `env -i PATH=/usr/bin:/bin bash run.sh`.
#
# Writes to $OUT (default: out/ beside this script) summary.txt (what it prints), details.log
# (every command's full output), and per capture the CUDA run's per-frame timings (*_cuda.csv)
# and trajectory (*_cuda_traj.txt): six files, two folders deep at most.
#
# Steps, each bounded by `timeout`, about 2-4 minutes of GPU time in all (the sanitizer runs are
# skipped once GPU_CHECK_BUDGET_S, default 420 s, is spent):
#   1. the GPU, the driver, and glibc against what the bundle needs
#   2. cuda_memory_test; fusion_bench refusing to start on a nearly full GPU, and stopping cleanly
#      when the brick pool cannot grow any more
#   3. cuda_parity_test: largest TSDF difference and pose difference, CPU against CUDA
#   4. fusion_bench on both captures and the synthetic room, CUDA and CPU: ms per stage (medians)
#      and per frame, ATE; the room's frame rate against teddy's; fr1_xyz end to end (decoding
#      included) on both backends
#   5. compute-sanitizer memcheck, racecheck, initcheck and synccheck on 5 frames, where it exists
# Exit status: 0 when every step passed or there is no NVIDIA device (a "no GPU" line says so),
# else 1 (a device the bundle cannot use is a failure too).
set -u
HERE=$(cd "$(dirname "$0")" && pwd)
OUT=${OUT:-$HERE/out}
mkdir -p "$OUT" || { echo "cannot create $OUT"; exit 1; }
OUT=$(cd "$OUT" && pwd)
SUMMARY=$OUT/summary.txt
DETAILS=$OUT/details.log
: >"$SUMMARY"
: >"$DETAILS"
export VDBFUSE_DATA_DIR=$HERE/data
BIN=$HERE/bin
BUDGET_S=${GPU_CHECK_BUDGET_S:-420}
START_S=$(date +%s)
FAILURES=0
FR1=$HERE/data/tum_fr1_xyz_head100
TEDDY=$HERE/data/tum_fr3_teddy_head60

say() { echo "$*" | tee -a "$SUMMARY"; }
fail() {
  say "FAIL $*"
  FAILURES=$((FAILURES + 1))
}
elapsed() { echo $(($(date +%s) - START_S)); }
# run NAME SECONDS COMMAND...: full output to details.log and to $LAST; the exit status in $RC.
LAST=$(mktemp)
trap 'rm -f "$LAST"' EXIT
run() {
  local name=$1 seconds=$2
  shift 2
  echo "===== $name: $* (limit ${seconds}s, at $(elapsed)s)" >>"$DETAILS"
  timeout --kill-after=10 "$seconds" "$@" >"$LAST" 2>&1
  RC=$?
  cat "$LAST" >>"$DETAILS"
  echo "===== $name: exit $RC after $(elapsed)s" >>"$DETAILS"
  [ "$RC" -ne 124 ] && [ "$RC" -ne 137 ] || say "     ($name stopped at its ${seconds}s limit)"
}
# The gtest result line: "[  PASSED  ] 9 tests." plus failed and skipped counts.
gtest_result() {
  local passed failed skipped
  passed=$(grep -o '^\[  PASSED  \] [0-9]*' "$LAST" | grep -o '[0-9]*$')
  failed=$(grep -o '^\[  FAILED  \] [0-9]* test' "$LAST" | grep -o '[0-9]*' | head -1)
  skipped=$(grep -o '^\[  SKIPPED \] [0-9]* test' "$LAST" | grep -o '[0-9]*' | head -1)
  echo "${passed:-0} passed, ${failed:-0} failed, ${skipped:-0} skipped"
}

say "vdbfuse GPU check: $(sed -n 2p "$HERE/MANIFEST" 2>/dev/null), $(date -u +%Y-%m-%dT%H:%M:%SZ)"

# ---- 1. GPU, driver, glibc ----------------------------------------------------------------------
needed=$(awk '$1 == "glibc_needed" {print $2}' "$HERE/MANIFEST" 2>/dev/null)
have=$(getconf GNU_LIBC_VERSION 2>/dev/null | awk '{print $2}')
# LAUNCH prefixes every program: empty, or the bundle's own glibc loader where this machine's glibc
# is older than the programs need (the driver's libcuda, built for old glibcs, loads under it too).
LAUNCH=()
if [ -n "$needed" ] && [ -n "$have" ] &&
   [ "$(printf '%s\n%s\n' "$needed" "$have" | sort -t. -k1,1n -k2,2n | head -1)" != "$needed" ]; then
  if [ ! -x "$HERE/glibc/ld-linux-x86-64.so.2" ]; then
    say "FAIL glibc $have here, the bundle's programs need $needed and it carries no glibc/: rebuild the bundle"
    exit 1
  fi
  LAUNCH=("$HERE/glibc/ld-linux-x86-64.so.2" --library-path "$HERE/glibc:$HERE/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}")
  say "glibc $have here, older than the $needed the programs need: they run on the bundle's own glibc"
fi
run gpu-info 60 "${LAUNCH[@]}" "$BIN/fusion_bench" --gpu-info
if [ "$RC" -ne 0 ]; then
  reason=$(head -1 "$LAST")
  # An NVIDIA device the bundle cannot use (driver older than its CUDA runtime, a GPU it has no
  # kernels for) is a failure, not a machine without a GPU.
  if ls /dev/nvidia[0-9]* >/dev/null 2>&1; then
    say "FAIL GPU present (/dev/nvidia*) but unusable by this bundle (CUDA 13, sm_90): ${reason#no CUDA GPU: }"
    exit 1
  fi
  # Still show that the programs load and run here: the no-GPU path of the memory test.
  run no-gpu-discovery 60 "${LAUNCH[@]}" "$BIN/cuda_memory_test" --gtest_filter='CudaDiscovery.*'
  say "no GPU: ${reason#no CUDA GPU: } (the programs load and run: cuda_memory_test discovery $(gtest_result)); nothing else to check here"
  exit 0
fi
say "GPU: $(head -1 "$LAST")"
if command -v nvidia-smi >/dev/null 2>&1; then
  say "     $(nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>/dev/null | head -1)"
fi
say "     glibc ${have:-?} (bundle needs ${needed:-?})"

# ---- 2. memory ----------------------------------------------------------------------------------
run cuda_memory_test 180 "${LAUNCH[@]}" "$BIN/cuda_memory_test"
if [ "$RC" -eq 0 ]; then say "memory tests: $(gtest_result)"; else fail "memory tests: exit $RC, $(gtest_result) (details.log)"; fi
# A GPU with 32 MiB free: the start-up check refuses at once, naming what is needed and free.
run gpu-memory-check 120 "${LAUNCH[@]}" "$BIN/fusion_bench" "$TEDDY" --device cuda --leave-gpu-mib 32 --max-frames 1
if [ "$RC" -eq 1 ] && grep -q "of GPU memory to start" "$LAST"; then
  say "GPU memory check: refused to start with 32 MiB free: $(grep -o 'needs .* free of [0-9.]* GiB' "$LAST" | head -1)"
else
  fail "GPU memory check: a start with 32 MiB free was not refused (exit $RC): $(tail -1 "$LAST")"
fi
# A GPU with 300 MiB free: the brick pool cannot double past it; the run stops and says so.
run gpu-volume-full 120 "${LAUNCH[@]}" "$BIN/fusion_bench" "$TEDDY" --device cuda --leave-gpu-mib 300 --voxel-size-m 0.002
if [ "$RC" -eq 0 ] && grep -q "volume full after frame" "$LAST"; then
  say "GPU volume full: $(grep -o 'volume full after frame .*' "$LAST" | head -1)"
else
  fail "GPU volume full: a 300 MiB GPU did not stop the run cleanly (exit $RC): $(tail -1 "$LAST")"
fi

# ---- 3. parity ----------------------------------------------------------------------------------
run cuda_parity_test 300 "${LAUNCH[@]}" "$BIN/cuda_parity_test"
if [ "$RC" -eq 0 ]; then say "parity tests: $(gtest_result)"; else fail "parity tests: exit $RC, $(gtest_result) (details.log)"; fi
grep '^\[parity\]' "$LAST" | sed 's/^\[parity\] /     /' | tee -a "$SUMMARY"

# ---- 4. benchmark -------------------------------------------------------------------------------
declare -A FPS  # frames/s from the four stages' medians, by "name device"
declare -A E2E  # frames/s end to end (--end-to-end: decoding included), by "name device"
# bench NAME FOLDER|--synthetic-room DEVICE [extra fusion_bench options]; BENCH_ENV (NAME=VALUE
# words) goes into fusion_bench's environment.
bench() {
  local name=$1 folder=$2 device=$3
  shift 3
  # shellcheck disable=SC2086
  run "bench-$name-$device" 240 env ${BENCH_ENV:-} "${LAUNCH[@]}" "$BIN/fusion_bench" "$folder" --device "$device" "$@"
  local line
  line=$(grep '^summary:' "$LAST" | sed 's/^summary: //')
  if [ "$RC" -eq 0 ] && [ -n "$line" ]; then
    say "bench $name $device: $line"
    FPS["$name $device"]=$(echo "$line" | sed -n 's/.* fps=\([0-9.]*\).*/\1/p')
    E2E["$name $device"]=$(echo "$line" | sed -n 's/.* e2e_fps=\([0-9.]*\).*/\1/p')
  else
    fail "bench $name $device: exit $RC: $(tail -1 "$LAST")"
  fi
}
say "bench (ms: medians per stage, frame_ms = their sum; ATE against the ground truth; the default 5.86 mm voxels):"
bench fr1_xyz "$FR1" cuda --timings "$OUT/fr1_xyz_cuda.csv" --trajectory "$OUT/fr1_xyz_cuda_traj.txt"
bench teddy "$TEDDY" cuda --timings "$OUT/teddy_cuda.csv" --trajectory "$OUT/teddy_cuda_traj.txt"
# fr1_xyz again with a wait after every launch (VDBFUSE_CUDA_SYNC=1), as the engine ran before its
# launches were stream-ordered (cuda/parallel.cuh): what the stream order is worth on this GPU.
BENCH_ENV=VDBFUSE_CUDA_SYNC=1 bench fr1_xyz_sync_each_launch "$FR1" cuda
bench fr1_xyz "$FR1" cpu
bench teddy "$TEDDY" cpu
# Issue 12's large scene, rendered in memory there: the 8 x 6 m room, 300 frames, a full turn.
bench room --synthetic-room cuda
bench room --synthetic-room cpu
# Issue 40's acceptance 3: fr1_xyz end to end, decoding included (on as many threads as
# reconstruct gives the device), the GPU against the CPU on this machine.
bench fr1_xyz_end_to_end "$FR1" cuda --end-to-end
bench fr1_xyz_end_to_end "$FR1" cpu --end-to-end
gpu=${E2E["fr1_xyz_end_to_end cuda"]:-} cpu=${E2E["fr1_xyz_end_to_end cpu"]:-}
[ -n "$gpu" ] && [ -n "$cpu" ] &&
  say "fr1_xyz end to end, cuda / cpu frames/s: $(awk -v g="$gpu" -v c="$cpu" 'BEGIN {printf "%.1f", g / c}') (issue 40 asks >= 10)"
for device in cuda cpu; do
  room=${FPS["room $device"]:-} teddy=${FPS["teddy $device"]:-}
  [ -n "$room" ] && [ -n "$teddy" ] &&
    say "room / teddy frames/s, $device: $(awk -v r="$room" -v t="$teddy" 'BEGIN {printf "%.2f", r / t}') (issue 12 asks >= 0.8)"
done

# ---- 5. compute-sanitizer -----------------------------------------------------------------------
SANITIZER=$(command -v compute-sanitizer 2>/dev/null)
if [ -z "$SANITIZER" ]; then
  for candidate in /usr/local/cuda*/bin/compute-sanitizer /opt/nvidia/*/compute-sanitizer/compute-sanitizer; do
    [ -x "$candidate" ] && { SANITIZER=$candidate; break; }
  done
fi
if [ -z "$SANITIZER" ]; then
  say "compute-sanitizer: not found (PATH, /usr/local/cuda*/bin): skipped"
else
  for tool in memcheck racecheck initcheck synccheck; do
    if [ "$(elapsed)" -gt "$BUDGET_S" ]; then
      say "compute-sanitizer $tool: skipped, the check has run $(elapsed)s of its ${BUDGET_S}s budget"
      continue
    fi
    case $tool in
      memcheck) options="--leak-check full" ;;
      racecheck) options="--racecheck-report all" ;;
      *) options="" ;;
    esac
    # shellcheck disable=SC2086
    run "sanitizer-$tool" 150 "$SANITIZER" --tool "$tool" $options --error-exitcode 99 \
      "${LAUNCH[@]}" "$BIN/fusion_bench" "$FR1" --device cuda --max-frames 5
    errors=$(grep -o 'ERROR SUMMARY: [0-9]* error' "$LAST" | grep -o '[0-9]*' | tail -1)
    if [ "$RC" -eq 0 ]; then
      say "compute-sanitizer $tool (5 frames): ${errors:-0} errors"
    else
      fail "compute-sanitizer $tool (5 frames): exit $RC, ${errors:-?} errors: $(grep -m1 -E '=+ (Invalid|Race|Uninitialized|Error|Program hit)' "$LAST")"
    fi
  done
fi

if [ "$FAILURES" -eq 0 ]; then
  say "GPU check passed: every step, in $(elapsed)s"
  exit 0
fi
say "GPU check FAILED: $FAILURES steps (details.log), in $(elapsed)s"
exit 1
