#pragma once
// What a mistyped command line gets. CLI11 on its own answers `--voxel-szie-m 0.01` with "The
// following arguments were not expected: 0.01 --voxel-szie-m", and a misspelt command with "A
// subcommand is required"; a user then has to read --help to find the typo. This names the
// command, the word it did not know and the closest name it does know.
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace vf::app {

// Prints the parse error to stderr as "PROGRAM COMMAND: ..." with suggestions; returns the exit
// status. Help and --version requests are printed as CLI11 prints them. vdbfuse-view, which has
// no commands, shares it.
int reportParseError(CLI::App& root, const CLI::ParseError& error, const std::string& program);

// CLI11's ExistingFile / ExistingPath, with the names beside a missing one that it was probably
// meant to be (core/similar_names.h) instead of "File does not exist: PATH".
CLI::Validator existingFile();
CLI::Validator existingPath();

}  // namespace vf::app
