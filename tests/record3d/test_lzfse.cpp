// LZFSE decoding against bytes produced by Apple's reference lzfse.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "io/lzfse.h"
#include "test_data.h"

namespace vf {
namespace {

std::vector<uint8_t> readFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

std::vector<uint8_t> bytesOf(std::initializer_list<int> v) {
  std::vector<uint8_t> out;
  for (int b : v) out.push_back(uint8_t(b));
  return out;
}
void append(std::vector<uint8_t>& a, const std::vector<uint8_t>& b) { a.insert(a.end(), b.begin(), b.end()); }
void appendU32(std::vector<uint8_t>& a, uint32_t v) {
  for (int i = 0; i < 4; ++i) a.push_back(uint8_t(v >> (8 * i)));
}
std::string asString(const std::vector<uint8_t>& v) { return std::string(v.begin(), v.end()); }

TEST(Lzfse, UncompressedBlockIsCopied) {
  std::vector<uint8_t> s = bytesOf({'b', 'v', 'x', '-'});
  appendU32(s, 5);
  append(s, bytesOf({'h', 'e', 'l', 'l', 'o', 'b', 'v', 'x', '$'}));
  EXPECT_EQ(asString(lzfseDecode(s)), "hello");
}

// Hand-assembled LZVN: small literal "abc", small-distance match (D 3, M 8), previous-distance
// op with one literal 'x' (M 3), small match M 1 with the previous distance, end of stream.
std::vector<uint8_t> lzvnStream() {
  const auto payload = bytesOf({0xE3, 'a', 'b', 'c', 0x28, 0x03, 0x46, 'x', 0xF1,
                                0x06, 0, 0, 0, 0, 0, 0, 0});
  std::vector<uint8_t> s = bytesOf({'b', 'v', 'x', 'n'});
  appendU32(s, 16);
  appendU32(s, uint32_t(payload.size()));
  append(s, payload);
  append(s, bytesOf({'b', 'v', 'x', '$'}));
  return s;
}

TEST(Lzfse, LzvnOpcodesDecode) {
  EXPECT_EQ(asString(lzfseDecode(lzvnStream())), "abcabcabcabxabxa");
}

TEST(Lzfse, LzvnRejectsWrongSizeUndefinedOpcodeAndBadDistance) {
  auto wrong_size = lzvnStream();
  wrong_size[4] = 17;  // header says 17 bytes, stream yields 16
  EXPECT_THROW(lzfseDecode(wrong_size), Error);
  auto undefined = lzvnStream();
  undefined[12 + 4] = 0x70;  // 0111xxxx is undefined
  EXPECT_THROW(lzfseDecode(undefined), Error);
  auto far = lzvnStream();
  far[12 + 5] = 0x09;  // distance 9 with only 3 bytes decoded
  EXPECT_THROW(lzfseDecode(far), Error);
}

TEST(Lzfse, DepthFrameMatchesReferenceDecodeByteForByte) {
  VF_REQUIRE_DATA(src_path, "lzfse_reference/0.depth");
  VF_REQUIRE_DATA(ref_path, "lzfse_reference/0.depth.decoded_f32_256x192");
  const auto src = readFile(src_path);
  const auto ref = readFile(ref_path);
  ASSERT_EQ(ref.size(), 256u * 192u * 4u);
  const auto out = lzfseDecode(src);
  ASSERT_EQ(out.size(), ref.size());
  EXPECT_EQ(0, std::memcmp(out.data(), ref.data(), ref.size()));
}

TEST(Lzfse, ConfidenceFrameMatchesReferenceDecodeByteForByte) {
  VF_REQUIRE_DATA(src_path, "lzfse_reference/0.conf");
  VF_REQUIRE_DATA(ref_path, "lzfse_reference/0.conf.decoded_u8_256x192");
  const auto src = readFile(src_path);
  const auto ref = readFile(ref_path);
  const auto out = lzfseDecode(src, ref.size());
  ASSERT_EQ(out.size(), 49152u);
  EXPECT_EQ(out, ref);
  for (uint8_t c : out) ASSERT_LE(c, 2) << "confidence is 0, 1 or 2";
}

TEST(Lzfse, DecodeIntoExactBufferMatchesAndRejectsSmallerBuffer) {
  VF_REQUIRE_DATA(src_path, "lzfse_reference/0.depth");
  VF_REQUIRE_DATA(ref_path, "lzfse_reference/0.depth.decoded_f32_256x192");
  const auto src = readFile(src_path);
  const auto ref = readFile(ref_path);
  std::vector<uint8_t> dst(ref.size());
  EXPECT_EQ(lzfseDecodeInto(src.data(), src.size(), dst.data(), dst.size()), ref.size());
  EXPECT_EQ(dst, ref);
  std::vector<uint8_t> small(ref.size() - 1);
  EXPECT_THROW(lzfseDecodeInto(src.data(), src.size(), small.data(), small.size()), Error);
}

TEST(Lzfse, OutputLimitIsEnforced) {
  VF_REQUIRE_DATA(src_path, "lzfse_reference/0.depth");
  const auto src = readFile(src_path);
  EXPECT_THROW(lzfseDecode(src.data(), src.size(), 0, 100000), Error);
}

}  // namespace
}  // namespace vf
