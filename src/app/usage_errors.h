#pragma once
// What a mistyped command line gets. CLI11 on its own answers `--voxel-szie-m 0.01` with "The
// following arguments were not expected: 0.01 --voxel-szie-m", and a misspelt command with "A
// subcommand is required"; a user then has to read --help to find the typo. This names the
// command, the word it did not know and the closest name it does know.
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace vf::app {

// Edit distance with adjacent transpositions ("szie" -> "size" is one edit).
int typoDistance(const std::string& a, const std::string& b);

// The names `word` was probably meant to be: the closest one within a few edits, else the few that
// contain it; none when nothing is close enough to help.
std::vector<std::string> likelyNames(const std::string& word, const std::vector<std::string>& candidates);

// Prints the parse error to stderr as "PROGRAM COMMAND: ..." with suggestions; returns the exit
// status. Help and --version requests are printed as CLI11 prints them. vdbfuse-view, which has
// no commands, shares it.
int reportParseError(CLI::App& root, const CLI::ParseError& error, const std::string& program);

}  // namespace vf::app
