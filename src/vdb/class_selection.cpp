#include "vdb/class_selection.h"

#include "core/error.h"

namespace vf {
std::set<int> resolveClassSelection(const ClassTable& table, const std::vector<std::string>& items,
                                    const std::string& option) {
  if (table.empty())
    throw Error(option + ": the scene has no class table (it was fused without label maps)");
  const std::vector<int> ids = table.resolve(items, option);
  return std::set<int>(ids.begin(), ids.end());
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
