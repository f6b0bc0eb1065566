#include "vdb/class_selection.h"

#include <cctype>

#include "core/error.h"

namespace vf {
namespace {

std::string trim(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

bool isInteger(const std::string& s) {
  if (s.empty()) return false;
  for (size_t i = (s[0] == '-' ? 1 : 0); i < s.size(); ++i)
    if (!std::isdigit(static_cast<unsigned char>(s[i]))) return false;
  return s != "-";
}

std::string validNames(const ClassTable& table) {
  std::string out;
  for (const ClassInfo& c : table.classes)
    out += (out.empty() ? "" : ", ") + c.name + " (" + std::to_string(c.id) + ")";
  return out;
}

}  // namespace

std::set<int> resolveClassSelection(const ClassTable& table, const std::vector<std::string>& items,
                                    const std::string& option) {
  if (table.empty())
    throw Error(option + ": the scene has no class table (it was fused without label maps)");
  std::set<int> ids;
  for (const std::string& item : items) {
    size_t start = 0;
    while (start <= item.size()) {
      const size_t comma = item.find(',', start);
      const std::string token = trim(item.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
      start = comma == std::string::npos ? item.size() + 1 : comma + 1;
      if (token.empty()) continue;
      const ClassInfo* c = table.findName(token);
      if (!c && isInteger(token)) c = table.findId(std::stoi(token));
      if (!c) throw Error(option + ": unknown class '" + token + "'; valid classes: " + validNames(table));
      ids.insert(c->id);
    }
  }
  if (ids.empty()) throw Error(option + ": no class given; valid classes: " + validNames(table));
  return ids;
}

std::string classNames(const ClassTable& table, const std::set<int>& ids) {
  std::string out;
  for (int id : ids) {
    const ClassInfo* c = table.findId(id);
    out += (out.empty() ? "" : ", ") + (c ? c->name : std::to_string(id));
  }
  return out;
}

}  // namespace vf
