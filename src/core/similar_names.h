#pragma once
// The names a mistyped one was probably meant to be: options and commands on the command line
// (app/usage_errors.h), and files that do not exist beside ones that do.
#include <string>
#include <vector>

namespace vf {

// Edit distance with adjacent transpositions ("szie" -> "size" is one edit).
int typoDistance(const std::string& a, const std::string& b);

// The closest candidates within a few edits (leading dashes ignored; at most three, in name
// order), else the few that contain `word`; none when nothing is close enough to help.
std::vector<std::string> likelyNames(const std::string& word, const std::vector<std::string>& candidates);

// " (did you mean a, b or c?)", each name between `quote`s; "" for no names.
std::string didYouMean(const std::vector<std::string>& names, const std::string& quote = "");

// "PATH: no such file or folder", or with `what` ("scene file") "PATH: no such scene file", and
// the entries of its folder that it was probably meant to be: "(did you mean DIR/NAME?)".
std::string noSuchPathMessage(const std::string& path, const std::string& what = "file or folder");

}  // namespace vf
