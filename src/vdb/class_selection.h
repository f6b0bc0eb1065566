#pragma once
// Turning --include-classes / --exclude-classes arguments into class ids.
#include <set>
#include <string>
#include <vector>

#include "core/class_table.h"

namespace vf {

// Each item is a class name or a numeric id from `table` (comma-separated lists are split).
// Throws vf::Error naming `option` for an unknown name/id (listing the valid names), an empty
// list, or a scene without a class table.
std::set<int> resolveClassSelection(const ClassTable& table, const std::vector<std::string>& items,
                                    const std::string& option);

// "person, chair" for messages.
std::string classNames(const ClassTable& table, const std::set<int>& ids);

}  // namespace vf
