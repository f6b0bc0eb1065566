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

void ClassTable::requireUnique(const std::string& source) const {
  std::vector<const ClassInfo*> by_id;
  for (const ClassInfo& c : classes) {
    if (c.name.empty()) throw Error(source + ": class " + std::to_string(c.id) + " has an empty name");
    by_id.push_back(&c);
  }
  std::stable_sort(by_id.begin(), by_id.end(), [](const ClassInfo* a, const ClassInfo* b) { return a->id < b->id; });
  for (size_t i = 1; i < by_id.size(); ++i)
    if (by_id[i - 1]->id == by_id[i]->id)
      throw Error(source + ": class id " + std::to_string(by_id[i]->id) + " appears twice ('" + by_id[i - 1]->name +
                  "' and '" + by_id[i]->name + "')");
  std::stable_sort(by_id.begin(), by_id.end(), [](const ClassInfo* a, const ClassInfo* b) { return a->name < b->name; });
  for (size_t i = 1; i < by_id.size(); ++i)
    if (by_id[i - 1]->name == by_id[i]->name)
      throw Error(source + ": class name '" + by_id[i]->name + "' appears twice (ids " + std::to_string(by_id[i - 1]->id) +
                  " and " + std::to_string(by_id[i]->id) + ")");
}

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
