#include "io/frame_order.h"

#include <algorithm>
#include <cctype>

#include "core/error.h"

namespace vf {
namespace {

bool isDigit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

// The name without its last extension ("frame-000001.depth.png" -> "frame-000001.depth").
std::string withoutExtension(const std::string& name) {
  const size_t dot = name.rfind('.');
  return dot == std::string::npos || dot == 0 ? name : name.substr(0, dot);
}

// Compares the digit runs a[i..) and b[j..) as numbers of any length (no overflow), and moves i
// and j past them.
int compareNumberRuns(const std::string& a, size_t& i, const std::string& b, size_t& j) {
  while (i < a.size() && a[i] == '0' && i + 1 < a.size() && isDigit(a[i + 1])) ++i;  // leading zeros
  while (j < b.size() && b[j] == '0' && j + 1 < b.size() && isDigit(b[j + 1])) ++j;
  size_t ei = i, ej = j;
  while (ei < a.size() && isDigit(a[ei])) ++ei;
  while (ej < b.size() && isDigit(b[ej])) ++ej;
  int order = 0;
  if (ei - i != ej - j) {
    order = ei - i < ej - j ? -1 : 1;  // fewer significant digits: smaller
  } else {
    const int c = a.compare(i, ei - i, b, j, ej - j);
    order = c < 0 ? -1 : c > 0 ? 1 : 0;
  }
  i = ei, j = ej;
  return order;
}

}  // namespace

int compareFrameNames(const std::string& a_name, const std::string& b_name) {
  const std::string a = withoutExtension(a_name), b = withoutExtension(b_name);
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (isDigit(a[i]) && isDigit(b[j])) {
      if (const int order = compareNumberRuns(a, i, b, j)) return order;
      continue;
    }
    if (a[i] != b[j]) return (unsigned char)a[i] < (unsigned char)b[j] ? -1 : 1;
    ++i, ++j;
  }
  if (i < a.size()) return 1;
  if (j < b.size()) return -1;
  return 0;
}

void sortByFrameNumber(std::vector<std::string>& names, const std::string& folder) {
  // Ties (same frame) keep a fixed order, so the error names the same two files every run.
  std::sort(names.begin(), names.end(), [](const std::string& a, const std::string& b) {
    const int order = compareFrameNames(a, b);
    return order != 0 ? order < 0 : a < b;
  });
  for (size_t k = 1; k < names.size(); ++k)
    if (compareFrameNames(names[k - 1], names[k]) == 0)
      throw Error(folder + ": " + names[k - 1] + " and " + names[k] +
                  " name the same frame; keep one (both would be fused, the frame twice)");
}

}  // namespace vf
