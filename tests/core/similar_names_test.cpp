// The names a mistyped one was meant to be (core/similar_names.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/similar_names.h"
#include "test_data.h"

namespace vf {
namespace {

using Names = std::vector<std::string>;

TEST(SimilarNames, TranspositionIsOneEdit) {
  EXPECT_EQ(typoDistance("voxel-szie-m", "voxel-size-m"), 1);
  EXPECT_EQ(typoDistance("recontruct", "reconstruct"), 1);
  EXPECT_EQ(typoDistance("formt", "force"), 2);
  EXPECT_EQ(typoDistance("", "abc"), 3);
  EXPECT_EQ(typoDistance("kitten", "sitting"), 3);
}

TEST(SimilarNames, ClosestWithinAFewEditsElseThoseThatContainTheWord) {
  const Names options = {"--voxel-size-m", "--max-depth-m", "--include-classes", "--exclude-classes", "--force"};
  EXPECT_EQ(likelyNames("--voxel-szie-m", options), Names{"--voxel-size-m"});
  EXPECT_EQ(likelyNames("--max-depth", options), Names{"--max-depth-m"});
  EXPECT_EQ(likelyNames("--classes", options), (Names{"--include-classes", "--exclude-classes"}));
  EXPECT_TRUE(likelyNames("--formt", options).empty());  // two edits in five letters: another word
  EXPECT_TRUE(likelyNames("--", options).empty());
  // Ties all come, in name order, whatever order the candidates had.
  EXPECT_EQ(likelyNames("fr.vdb", {"rf.vdb", "x.ply", "fr1.vdb"}), (Names{"fr1.vdb", "rf.vdb"}));
  EXPECT_TRUE(likelyNames("a.vdb", {"b.vdb", "c.vdb", "d.vdb", "e.vdb"}).empty());  // too many to help
}

TEST(SimilarNames, AMissingPathNamesItsLikelyNeighbour) {
  const std::string dir = test::tempDir("similar_names");
  std::ofstream(dir + "/scene.vdb") << "x";
  std::filesystem::create_directories(dir + "/tum_fr1_xyz_head100");
  EXPECT_EQ(noSuchPathMessage(dir + "/scnee.vdb", "scene file"),
            dir + "/scnee.vdb: no such scene file (did you mean " + dir + "/scene.vdb?)");
  EXPECT_EQ(noSuchPathMessage(dir + "/tum_fr1_xyz_hed100/"),
            dir + "/tum_fr1_xyz_hed100/: no such file or folder (did you mean " + dir + "/tum_fr1_xyz_head100?)");
  EXPECT_EQ(noSuchPathMessage(dir + "/other.txt"), dir + "/other.txt: no such file or folder");
  EXPECT_EQ(noSuchPathMessage(dir + "/missing_folder/scene.vdb"),
            dir + "/missing_folder/scene.vdb: no such file or folder");
}

}  // namespace
}  // namespace vf
