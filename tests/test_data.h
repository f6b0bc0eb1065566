#pragma once
// Where tests find the shared real captures. A test that needs data calls requireData(), which
// fails (never skips) with the path it looked for, so a missing ../shared is loud in CI.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace vf::test {

inline std::string dataPath(const std::string& relative) {
  return std::string(VDBFUSE_DATA_DIR) + "/" + relative;
}

// Returns the absolute path, or records a fatal failure naming it when it does not exist.
#define VF_REQUIRE_DATA(var, relative)                                                  \
  const std::string var = ::vf::test::dataPath(relative);                               \
  ASSERT_TRUE(std::filesystem::exists(var))                                             \
      << "test data not found: " << var                                                 \
      << " (the shared data folder must sit beside the project as ../shared/data)"

inline std::string tempDir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("vdbfuse_test_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

}  // namespace vf::test
