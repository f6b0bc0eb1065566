// Hostile input: truncated, bit-flipped and lying LZFSE streams must throw vf::Error, never
// crash, hang or allocate what a header claims. Run under AddressSanitizer (build-r3d-asan).
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <random>

#include "core/error.h"
#include "io/lzfse.h"
#include "test_data.h"

namespace vf {
namespace {

std::vector<uint8_t> readFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// Returns true when decoding threw vf::Error; a success must yield the expected size.
bool decodeFails(const std::vector<uint8_t>& s, size_t expected_size) {
  try {
    const auto out = lzfseDecode(s);
    EXPECT_EQ(out.size(), expected_size) << "a stream that decodes must keep its declared size";
    return false;
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("LZFSE: ", 0), 0u) << e.what();
    return true;
  }
}

TEST(LzfseCorruption, EveryTruncationOfTheConfidenceStreamThrows) {
  VF_REQUIRE_DATA(path, "lzfse_reference/0.conf");
  const auto src = readFile(path);
  ASSERT_EQ(src.size(), 2713u);
  for (size_t cut = 0; cut < src.size(); ++cut) {
    const std::vector<uint8_t> part(src.begin(), src.begin() + cut);
    EXPECT_THROW(lzfseDecode(part), Error) << "cut at " << cut;
  }
}

TEST(LzfseCorruption, TruncationsOfTheDepthStreamThrow) {
  VF_REQUIRE_DATA(path, "lzfse_reference/0.depth");
  const auto src = readFile(path);
  int tried = 0;
  for (size_t cut = 0; cut < src.size(); cut += (cut < 1024 ? 1 : 97)) {
    const std::vector<uint8_t> part(src.begin(), src.begin() + cut);
    EXPECT_THROW(lzfseDecode(part), Error) << "cut at " << cut;
    ++tried;
  }
  EXPECT_GT(tried, 1500);
}

TEST(LzfseCorruption, FlippedBytesThrowOrKeepTheDeclaredSize) {
  VF_REQUIRE_DATA(path, "lzfse_reference/0.depth");
  const auto src = readFile(path);
  std::mt19937 rng(1234);
  int failed = 0;
  const int trials = 3000;
  for (int t = 0; t < trials; ++t) {
    auto bad = src;
    const int flips = 1 + int(rng() % 4);
    for (int f = 0; f < flips; ++f) bad[rng() % bad.size()] ^= uint8_t(1 + rng() % 255);
    failed += decodeFails(bad, 196608);
  }
  // Most flips land in the entropy-coded payload and derail it; some only change a literal.
  EXPECT_GT(failed, trials / 4);
}

TEST(LzfseCorruption, EveryHeaderByteFlipIsSafe) {
  VF_REQUIRE_DATA(path, "lzfse_reference/0.conf");
  const auto src = readFile(path);
  for (size_t i = 0; i < 200 && i < src.size(); ++i) {
    for (uint8_t x : {0x01, 0x80, 0xff}) {
      auto bad = src;
      bad[i] ^= x;
      decodeFails(bad, 49152);
    }
  }
}

void setField(std::vector<uint8_t>& s, size_t word_offset, int bit, int nbits, uint64_t value) {
  uint64_t w;
  std::memcpy(&w, s.data() + word_offset, 8);
  const uint64_t mask = ((uint64_t(1) << nbits) - 1) << bit;
  w = (w & ~mask) | ((value << bit) & mask);
  std::memcpy(s.data() + word_offset, &w, 8);
}

TEST(LzfseCorruption, HeadersClaimingHugeSizesThrowBeforeAllocating) {
  VF_REQUIRE_DATA(path, "lzfse_reference/0.depth");
  const auto src = readFile(path);
  ASSERT_EQ(std::memcmp(src.data(), "bvx2", 4), 0);
  {
    auto bad = src;  // n_raw_bytes = 4 GiB - 1
    std::memset(bad.data() + 4, 0xff, 4);
    EXPECT_THROW(lzfseDecode(bad), Error);
  }
  {
    auto bad = src;  // n_literals = 2^20 - 1 (limit 40000)
    setField(bad, 8, 0, 20, 0xfffff);
    EXPECT_THROW(lzfseDecode(bad), Error);
  }
  {
    auto bad = src;  // literal payload = 2^20 - 1 bytes: past the end of the input
    setField(bad, 8, 20, 20, 0xfffff);
    EXPECT_THROW(lzfseDecode(bad), Error);
  }
  {
    auto bad = src;  // header size 4 GiB - 1
    setField(bad, 24, 0, 32, 0xffffffff);
    EXPECT_THROW(lzfseDecode(bad), Error);
  }
  {
    std::vector<uint8_t> bad = {'b', 'v', 'x', '-', 0xff, 0xff, 0xff, 0x7f, 1, 2, 3};
    EXPECT_THROW(lzfseDecode(bad), Error);  // uncompressed block of 2 GiB with 3 bytes present
  }
  {
    std::vector<uint8_t> bad = {'b', 'v', 'x', 'n', 0xff, 0xff, 0xff, 0xff, 16, 0, 0, 0};
    bad.resize(bad.size() + 16, 0xf0);  // LZVN claiming 4 GiB from 16 payload bytes
    bad.insert(bad.end(), {'b', 'v', 'x', '$'});
    EXPECT_THROW(lzfseDecode(bad), Error);
  }
}

TEST(LzfseCorruption, RandomBlocksBehindValidMagicsAreSafe) {
  std::mt19937 rng(99);
  const char* magics[] = {"bvx1", "bvx2", "bvxn", "bvx-"};
  for (int t = 0; t < 4000; ++t) {
    std::vector<uint8_t> s(4 + rng() % 1200);
    for (auto& b : s) b = uint8_t(rng());
    std::memcpy(s.data(), magics[t % 4], 4);
    if (t % 3 == 0 && s.size() > 16) std::memcpy(s.data() + 4, "\x00\x10\x00\x00", 4);
    try {
      lzfseDecode(s);
    } catch (const Error&) {
    }
  }
  SUCCEED();
}

TEST(LzfseCorruption, UnknownMagicNamesTheOffset) {
  std::vector<uint8_t> s = {'b', 'v', 'x', '-', 1, 0, 0, 0, 'a', 'j', 'u', 'n', 'k'};
  try {
    lzfseDecode(s);
    FAIL() << "expected vf::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("at byte 9"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vf
