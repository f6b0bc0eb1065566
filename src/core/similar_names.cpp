#include "core/similar_names.h"

#include <algorithm>
#include <filesystem>
#include <system_error>

namespace vf {

int typoDistance(const std::string& a, const std::string& b) {
  // Optimal string alignment over three rows of the table.
  const size_t n = a.size(), m = b.size();
  std::vector<int> before(m + 1), previous(m + 1), current(m + 1);
  for (size_t j = 0; j <= m; ++j) previous[j] = int(j);
  for (size_t i = 1; i <= n; ++i) {
    current[0] = int(i);
    for (size_t j = 1; j <= m; ++j) {
      const int substitution = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, substitution});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        current[j] = std::min(current[j], before[j - 2] + 1);
    }
    std::swap(before, previous);
    std::swap(previous, current);
  }
  return previous[m];
}

std::vector<std::string> likelyNames(const std::string& word, const std::vector<std::string>& candidates) {
  const auto bare = [](const std::string& s) { return s.substr(std::min(s.find_first_not_of('-'), s.size())); };
  const std::string w = bare(word);
  if (w.empty()) return {};
  // One edit in a short word, up to three in a long one: "--voxel-szie-m" finds "--voxel-size-m",
  // "--formt" does not find "--force".
  const int allowed = w.size() <= 5 ? 1 : w.size() <= 9 ? 2 : 3;
  // Every candidate at the least distance ("fr.vdb": fr1.vdb and rf.vdb), in name order, so
  // that a folder's listing order does not decide; more than three would not help.
  std::vector<std::string> closest;
  int best_distance = allowed + 1;
  for (const std::string& candidate : candidates) {
    const int d = typoDistance(w, bare(candidate));
    if (d > allowed) continue;
    if (d < best_distance) closest.clear(), best_distance = d;
    if (d == best_distance) closest.push_back(candidate);
  }
  std::sort(closest.begin(), closest.end());
  if (!closest.empty()) return closest.size() <= 3 ? closest : std::vector<std::string>{};
  // A part of a name: "--max-depth" for "--max-depth-m", "--classes" for "--include-classes"
  // and "--exclude-classes".
  std::vector<std::string> containing;
  for (const std::string& candidate : candidates)
    if (w.size() >= 3 && bare(candidate).find(w) != std::string::npos) containing.push_back(candidate);
  if (containing.size() > 3) containing.clear();  // too general to help
  return containing;
}

std::string didYouMean(const std::vector<std::string>& names, const std::string& quote) {
  if (names.empty()) return "";
  std::string out = " (did you mean ";
  for (size_t i = 0; i < names.size(); ++i)
    out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + (quote + names[i] + quote);
  return out + "?)";
}

std::string noSuchPathMessage(const std::string& path, const std::string& what) {
  namespace fs = std::filesystem;
  fs::path p(path);
  if (p.filename().empty()) p = p.parent_path();  // "dir/" names dir
  const fs::path folder = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::vector<std::string> names;
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end && names.size() < 100000; it.increment(ec))
    names.push_back(it->path().filename().string());
  std::vector<std::string> likely = likelyNames(p.filename().string(), names);
  if (p.has_parent_path())
    for (std::string& name : likely) name = (folder / name).string();
  return path + ": no such " + what + didYouMean(likely);
}

}  // namespace vf
