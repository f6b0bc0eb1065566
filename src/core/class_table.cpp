#include "core/class_table.h"

#include <algorithm>
#include <cctype>

#include "core/error.h"
#include "core/text_fields.h"

namespace vf {
namespace {

std::string trimmed(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

}  // namespace

std::string ClassTable::listing() const {
  std::string out;
  for (const ClassInfo& c : classes) out += (out.empty() ? "" : ", ") + c.name + " (" + std::to_string(c.id) + ")";
  return out.empty() ? "none: the class table is empty" : out;
}

std::vector<int> ClassTable::resolve(const std::vector<std::string>& items, const std::string& what) const {
  std::vector<int> ids;
  for (const std::string& item : items) {
    size_t start = 0;
    while (start <= item.size()) {
      const size_t comma = item.find(',', start);
      const std::string token = trimmed(item.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
      start = comma == std::string::npos ? item.size() + 1 : comma + 1;
      if (token.empty()) continue;
      const ClassInfo* c = findName(token);
      int id = 0;
      if (!c && parseInt(token, id)) c = findId(id);
      if (!c) throw Error(what + ": unknown class '" + token + "'; valid classes: " + listing());
      if (std::find(ids.begin(), ids.end(), c->id) == ids.end()) ids.push_back(c->id);
    }
  }
  if (ids.empty()) throw Error(what + ": no class given; valid classes: " + listing());
  return ids;
}

}  // namespace vf
