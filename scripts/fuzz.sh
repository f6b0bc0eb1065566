#!/usr/bin/env bash
# Fuzz each reader of outside data for a fixed time, one target after another, and print the
# executions count and any finding of each. This is the "≥ 10 minutes by hand" run of issue 8;
# CI runs the same targets for seconds (ctest -L fuzz).
#
#   bash scripts/fuzz.sh [SECONDS=600] [TARGET...]     (default: every target)
#
# Needs clang (libFuzzer). Builds build-fuzz with ASan+UBSan; new crashers land in
# tests/fuzz/regressions/<target>/, logs in build-fuzz/fuzz-logs/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-600}
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(tum_list image lzfse r3d r3d_metadata class_table trajectory scene dataset_text ply checkpoint dataset_json
           dataset_folder)
fi

if [ ! -f build-fuzz/build.ninja ]; then
  cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DVDBFUSE_FUZZ=ON -DVDBFUSE_WITH_CUDA=OFF -DVDBFUSE_WITH_VIEWER=OFF
fi
ninja -C build-fuzz "${targets[@]/#/fuzz_}"

mkdir -p build-fuzz/fuzz-logs
for t in "${targets[@]}"; do
  work=build-fuzz/tests/fuzz/corpus/$t
  mkdir -p "$work" "tests/fuzz/regressions/$t"
  log=build-fuzz/fuzz-logs/$t.log
  status=clean
  ASAN_OPTIONS=allocator_may_return_null=1 build-fuzz/tests/fuzz/fuzz_$t \
    -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=20 -print_final_stats=1 \
    -artifact_prefix="tests/fuzz/regressions/$t/" "$work" "tests/fuzz/corpus/$t" >"$log" 2>&1 ||
    status="FINDING (see $log)"
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  secs=$(grep -o 'stat::slowest_unit_time_sec: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  printf '%-13s %10s executions in %ss, slowest unit %ss: %s\n' "$t" "$runs" "$seconds" "$secs" "$status"
done
