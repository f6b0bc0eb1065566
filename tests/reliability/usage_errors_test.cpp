// What a mistyped command line gets (src/app/usage_errors.h): the command, the word it did not
// know and, where one is close, the name that was meant; nothing run, nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "reliability/cli_harness.h"

namespace vf::test {
namespace {

void expectRefused(const CliRun& run, const std::string& message) {
  EXPECT_NE(run.status, 0) << run.output;
  EXPECT_LT(run.status, 128) << "a typo must not crash: " << run.output;
  EXPECT_NE(run.output.find(message), std::string::npos) << "expected \"" << message << "\" in:\n" << run.output;
}

TEST(UsageErrors, MisspeltOptionNamesTheOptionMeant) {
  const std::filesystem::path out = std::filesystem::temp_directory_path() / "vf_usage_errors_scene.vdb";
  std::filesystem::remove(out);
  const CliRun run = runVdbfuse({"reconstruct", "no_such_sequence", "-o", out.string(), "--voxel-szie-m", "0.01"});
  expectRefused(run, "vdbfuse reconstruct: unknown option --voxel-szie-m (did you mean --voxel-size-m?)");
  expectRefused(run, "Run 'vdbfuse reconstruct --help' for its options.");
  // The option's value is not reported as a second mistake.
  EXPECT_EQ(run.output.find("0.01"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(UsageErrors, MisspeltCommandNamesTheCommandMeant) {
  expectRefused(runVdbfuse({"recontruct", "x"}), "vdbfuse: unknown command 'recontruct' (did you mean 'reconstruct'?)");
  expectRefused(runVdbfuse({}), "vdbfuse: no command given; the commands are reconstruct, ");
}

TEST(UsageErrors, PartOfANameListsTheOptionsThatContainIt) {
  expectRefused(runVdbfuse({"mesh", "a.vdb", "-o", "b.ply", "--classes", "person"}),
                "vdbfuse mesh: unknown option --classes (did you mean --include-classes or --exclude-classes?)");
  expectRefused(runVdbfuse({"reconstruct", "x", "-o", "y.vdb", "--max-depth=3"}),
                "unknown option --max-depth (did you mean --max-depth-m?)");
}

TEST(UsageErrors, NoSuggestionWhenNothingIsClose) {
  // export has --force but no --format: two edits in a five-letter word is a different word.
  const CliRun run = runVdbfuse({"export", "a.vdb", "-o", "b", "--formt", "ply"});
  expectRefused(run, "vdbfuse export: unknown option --formt\n");
  EXPECT_EQ(run.output.find("did you mean"), std::string::npos) << run.output;
}

TEST(UsageErrors, UnknownOptionComesBeforeWhatItLeftMissing) {
  // The typo is why the scene seems missing ("--min-weigth a.vdb" took the scene as its value).
  const CliRun run = runVdbfuse({"mesh", "--min-weigth", "a.vdb", "-o", "b.ply"});
  expectRefused(run, "vdbfuse mesh: unknown option --min-weigth (did you mean --min-weight?)");
  EXPECT_EQ(run.output.find("scene is required"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace vf::test
