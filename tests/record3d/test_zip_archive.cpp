#include <gtest/gtest.h>

#include <algorithm>
#include <thread>

#include "core/error.h"
#include "io/zip_archive.h"
#include "r3d_test_util.h"
#include "test_data.h"

namespace vf {
namespace {

using test::errorOf;

TEST(ZipArchive, ListsAndReadsTheSharedCapture) {
  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  VF_REQUIRE_DATA(ref, "lzfse_reference/0.depth");
  ZipArchive zip(r3d);
  EXPECT_EQ(zip.entryNames().size(), 602u);  // metadata, icon, 200 x (jpg, depth, conf)
  EXPECT_EQ(zip.entryNames()[0], "metadata");
  EXPECT_TRUE(zip.contains("rgbd/199.conf"));
  EXPECT_FALSE(zip.contains("rgbd/200.depth"));
  EXPECT_EQ(zip.entrySize("rgbd/0.depth"), 50530u);
  EXPECT_EQ(zip.read("rgbd/0.depth"), test::readFileBytes(ref));
}

TEST(ZipArchive, MissingEntryErrorNamesArchiveAndEntry) {
  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  ZipArchive zip(r3d);
  const std::string msg = errorOf([&] { zip.read("rgbd/999.depth"); });
  EXPECT_NE(msg.find(r3d), std::string::npos) << msg;
  EXPECT_NE(msg.find("rgbd/999.depth"), std::string::npos) << msg;
  EXPECT_THROW(zip.read("rgbd/0.jpg", 1000), Error);  // 82705 bytes > limit
}

TEST(ZipArchive, NotAZipAndTruncatedZipThrowNamingTheFile) {
  const std::string dir = test::tempDir("zip_bad");
  const std::string text = dir + "/notes.r3d";
  test::writeFileBytes(text, test::toBytes("this is not a zip archive at all"));
  EXPECT_NE(errorOf([&] { ZipArchive z(text); }).find(text), std::string::npos);
  EXPECT_NE(errorOf([&] { ZipArchive z(dir + "/missing.r3d"); }).find("missing.r3d"),
            std::string::npos);

  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  auto bytes = test::readFileBytes(r3d);
  for (size_t keep : {size_t(100), bytes.size() / 2, bytes.size() - 10}) {
    const std::string cut = dir + "/cut.r3d";
    test::writeFileBytes(cut, std::vector<uint8_t>(bytes.begin(), bytes.begin() + long(keep)));
    const std::string msg = errorOf([&] { ZipArchive z(cut); });
    EXPECT_NE(msg.find(cut), std::string::npos) << "kept " << keep << " bytes: '" << msg << "'";
  }
}

TEST(ZipArchive, ConcurrentReadsOfDifferentEntriesMatchSerialReads) {
  VF_REQUIRE_DATA(r3d, "record3d_dance_head200.r3d");
  ZipArchive zip(r3d);
  std::vector<std::vector<uint8_t>> serial(40), parallel(40);
  for (int i = 0; i < 40; ++i) serial[i] = zip.read("rgbd/" + std::to_string(i) + ".depth");
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (int i = t; i < 40; i += 4) parallel[i] = zip.read("rgbd/" + std::to_string(i) + ".depth");
    });
  for (auto& th : threads) th.join();
  EXPECT_EQ(serial, parallel);
}

}  // namespace
}  // namespace vf
