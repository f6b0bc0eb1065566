// LZFSE decode throughput on real Record3D frames, reported as decoded bytes per second.
//   ninja -C build-r3d bench_lzfse && build-r3d/tests/record3d/bench_lzfse
#include <benchmark/benchmark.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "io/lzfse.h"

namespace {

std::vector<uint8_t> readFile(const std::string& relative) {
  const std::string path = std::string(VDBFUSE_DATA_DIR) + "/" + relative;
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("benchmark data not found: " + path);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

void decodeVector(benchmark::State& state, const char* file) {
  const auto src = readFile(file);
  size_t decoded = vf::lzfseDecode(src).size();
  for (auto _ : state) {
    auto out = vf::lzfseDecode(src, decoded);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(decoded));
  state.counters["ratio"] = double(decoded) / double(src.size());
}

void decodeInto(benchmark::State& state, const char* file) {
  const auto src = readFile(file);
  std::vector<uint8_t> dst(vf::lzfseDecode(src).size());
  for (auto _ : state) {
    benchmark::DoNotOptimize(vf::lzfseDecodeInto(src.data(), src.size(), dst.data(), dst.size()));
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(dst.size()));
}

BENCHMARK_CAPTURE(decodeVector, depth_f32_192x256, "lzfse_reference/0.depth");
BENCHMARK_CAPTURE(decodeInto, depth_f32_192x256, "lzfse_reference/0.depth");
BENCHMARK_CAPTURE(decodeVector, conf_u8_192x256, "lzfse_reference/0.conf");
BENCHMARK_CAPTURE(decodeInto, conf_u8_192x256, "lzfse_reference/0.conf");

}  // namespace

BENCHMARK_MAIN();
