#include "core/text_fields.h"

#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>

namespace vf {

namespace {
// strtod and strtol skip leading blanks; a field has none.
bool startsClean(const std::string& field) { return !field.empty() && !std::isspace(static_cast<unsigned char>(field[0])); }
}  // namespace

bool parseDouble(const std::string& field, double& value) {
  if (!startsClean(field)) return false;
  char* end = nullptr;
  value = std::strtod(field.c_str(), &end);
  return end != field.c_str() && *end == '\0';
}

bool parseFiniteDouble(const std::string& field, double& value) {
  return parseDouble(field, value) && std::isfinite(value);
}

bool parseFiniteFloat(const std::string& field, float& value) {
  double v = 0;
  if (!parseFiniteDouble(field, v) || std::fabs(v) > double(3.4e38f)) return false;
  value = float(v);
  return true;
}

bool parseInt(const std::string& field, int& value) {
  if (!startsClean(field)) return false;
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(field.c_str(), &end, 10);
  if (end == field.c_str() || *end != '\0' || errno == ERANGE || v < INT_MIN || v > INT_MAX) return false;
  value = int(v);
  return true;
}

}  // namespace vf
