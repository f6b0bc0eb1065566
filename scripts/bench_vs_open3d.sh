#!/usr/bin/env bash
# vdbfuse against the Open3D 0.16 dense RGB-D SLAM peer (../shared/peers/open3d_slam, needs
# Debian's libopen3d-dev) on the same TUM folders, as whole processes (decoding, fusion and the
# scene write included): RUNS paired runs each, alternating which goes first, with the medians
# of wall time, CPU seconds (user + system) and peak memory, the ratios, vdbfuse's per-stage
# times, Open3D's own summary, and both ATEs.
#
# Open3D's OpenMP threads spin while they wait, so a machine whose cores are shared inflates its
# time more than vdbfuse's: before each pair the script measures how busy the CPUs are without
# it and flags every pair run on a busy machine (BUSY=refuse stops instead).
#
# Usage: scripts/bench_vs_open3d.sh [BUILD_DIR] [TUM_FOLDER...]
#   RUNS=3 (pairs per sequence)  BUSY=flag|refuse  BUSY_PERCENT=15 (other load, % of all cores)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=build
if [ $# -gt 0 ] && [ -d "$1/src/app" ]; then BUILD_DIR=$1; shift; fi
DATA=${VDBFUSE_DATA_DIR:-../shared/data}
RUNS=${RUNS:-3}
BUSY=${BUSY:-flag}
BUSY_PERCENT=${BUSY_PERCENT:-15}
SEQUENCES=("$@")
[ ${#SEQUENCES[@]} -gt 0 ] || SEQUENCES=("$DATA/tum_fr1_xyz_head100" "$DATA/tum_fr3_teddy_head60")
VF="$BUILD_DIR/src/app/vdbfuse"
[ -x "$VF" ] || { echo "bench_vs_open3d: $VF is missing; build it first (ninja -C $BUILD_DIR vdbfuse)" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "bench_vs_open3d: /usr/bin/time is missing (apt-get install time)" >&2; exit 2; }
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT

PEER=""
if [ -f /usr/include/open3d/Open3D.h ] || dpkg -s libopen3d-dev >/dev/null 2>&1; then
  cmake -S ../shared/peers/open3d_slam -B "$OUT/o3d_build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$OUT/o3d_build" -j "$(nproc)" >/dev/null
  PEER="$OUT/o3d_build/open3d_dense_slam"
else
  echo "libopen3d-dev is not installed: vdbfuse alone (apt-get install libopen3d-dev for the peer)"
fi

# Percent of all cores busy over one second, from /proc/stat (this script is idle meanwhile).
cpu_busy_percent() {
  local a b
  read -r -a a < <(grep '^cpu ' /proc/stat)
  sleep 1
  read -r -a b < <(grep '^cpu ' /proc/stat)
  local total=0 idle=0 i
  for i in 1 2 3 4 5 6 7 8; do total=$((total + b[i] - a[i])); done
  idle=$((b[4] - a[4] + b[5] - a[5]))
  echo $(( total > 0 ? 100 * (total - idle) / total : 0 ))
}

median() { sort -g | awk '{v[NR] = $1} END {if (NR == 0) print "nan"; else if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }

# run_timed NAME LOG COMMAND...: appends "wall cpu maxrss_kib" to $OUT/NAME.times
run_timed() {
  local name=$1 log=$2
  shift 2
  /usr/bin/time -f "%e %U %S %M" -o "$OUT/time.txt" "$@" >"$log" 2>&1 || { cat "$log"; return 1; }
  awk '{printf "%s %.2f %s\n", $1, $2 + $3, $4}' "$OUT/time.txt" >>"$OUT/$name.times"
}

busy_pairs=0
for seq in "${SEQUENCES[@]}"; do
  name=$(basename "$seq")
  rm -f "$OUT"/*.times
  echo "=== $name: $RUNS paired runs"
  for run in $(seq 1 "$RUNS"); do
    busy=$(cpu_busy_percent)
    flag=""
    if [ "$busy" -gt "$BUSY_PERCENT" ]; then
      busy_pairs=$((busy_pairs + 1))
      flag="  BUSY: ${busy}% of the CPUs in use before this pair"
      [ "$BUSY" = refuse ] && { echo "bench_vs_open3d: the machine is busy (${busy}% > ${BUSY_PERCENT}%); refusing (BUSY=flag runs anyway)" >&2; exit 3; }
    fi
    order=(vdbfuse open3d)
    [ $((run % 2)) -eq 0 ] && order=(open3d vdbfuse)
    for who in "${order[@]}"; do
      if [ "$who" = vdbfuse ]; then
        run_timed vdbfuse "$OUT/vdbfuse.log" "$VF" reconstruct "$seq" -o "$OUT/$name.vdb" -q -f --verbose \
          --trajectory "$OUT/$name.vdbfuse.txt"
      elif [ -n "$PEER" ]; then
        run_timed open3d "$OUT/open3d.log" "$PEER" --dataset "$seq" --out "$OUT/o3d_$name"
      fi
    done
    echo "  pair $run: vdbfuse $(tail -1 "$OUT/vdbfuse.times" | awk '{print $1 " s"}')${PEER:+, open3d $(tail -1 "$OUT/open3d.times" | awk '{print $1 " s"}')}$flag"
  done
  frames=$(sed -nE 's/^([0-9]+) frames in .*/\1/p' "$OUT/vdbfuse.log" | tail -1)
  printf "  %-9s %10s %10s %10s %9s\n" "" "wall s" "CPU s" "peak MiB" "frames/s"
  for who in vdbfuse open3d; do
    [ -f "$OUT/$who.times" ] || continue
    wall=$(awk '{print $1}' "$OUT/$who.times" | median)
    cpu=$(awk '{print $2}' "$OUT/$who.times" | median)
    mem=$(awk '{print $3 / 1024}' "$OUT/$who.times" | median)
    printf "  %-9s %10.2f %10.2f %10.0f %9.1f\n" "$who" "$wall" "$cpu" "$mem" "$(echo "$frames / $wall" | bc -l)"
    eval "${who}_wall=$wall ${who}_cpu=$cpu ${who}_mem=$mem"
  done
  if [ -n "$PEER" ]; then
    printf "  ratio (open3d / vdbfuse, medians): wall %.2fx, CPU %.2fx, memory %.2fx\n" \
      "$(echo "$open3d_wall / $vdbfuse_wall" | bc -l)" "$(echo "$open3d_cpu / $vdbfuse_cpu" | bc -l)" \
      "$(echo "$open3d_mem / $vdbfuse_mem" | bc -l)"
  fi
  echo "  vdbfuse stages (last run):"
  grep -E "^(measure|track|integrate|raycast|fusion) " "$OUT/vdbfuse.log" | sed 's/^/    /'
  echo -n "  vdbfuse ATE: "
  "$VF" evaluate --trajectory "$OUT/$name.vdbfuse.txt" --groundtruth "$seq/groundtruth.txt" | grep -A1 "^ATE" | tail -1
  if [ -n "$PEER" ]; then
    echo "  open3d stages (last run): $(grep SUMMARY "$OUT/o3d_$name/summary.txt" || true)"
    echo -n "  open3d ATE: "
    "$VF" evaluate --trajectory "$OUT/o3d_$name/trajectory.txt" --groundtruth "$seq/groundtruth.txt" | grep -A1 "^ATE" | tail -1
  fi
done
[ "$busy_pairs" -eq 0 ] || echo "WARNING: $busy_pairs pair(s) ran on a busy machine (flagged above): the ratios are not a quiet-machine figure"
