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

// Numeric bounds with messages a user reads ("--max-frames: must be at least 1, got 0"), for
// CLI11's Range / PositiveNumber / NonNegativeNumber, which print their bounds with
// std::to_string (a 309-digit number for "no upper bound") and let NaN through every range.
CLI::Validator atLeast(double min);
CLI::Validator inRange(double min, double max);

// Adds to every floating-point option of `app` and its commands a check that refuses a value
// that is not a finite number ("nan", "inf", 1e400): NaN passes every comparison, so it slipped
// past every range check into the library. Call once, after the options are set up.
void requireFiniteNumbers(CLI::App& app);

}  // namespace vf::app
