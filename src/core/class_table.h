#pragma once
#include <string>
#include <vector>

#include "core/math.h"

namespace vf {

// One semantic class: the id a label map uses, a human name, a display color.
struct ClassInfo {
  int id = 0;
  std::string name;
  Rgb8 color{128, 128, 128, 255};
};

// id -> name/color table shipped with label maps (ADE20K, COCO-stuff, person/background...).
struct ClassTable {
  std::vector<ClassInfo> classes;

  const ClassInfo* findId(int id) const {
    for (const ClassInfo& c : classes)
      if (c.id == id) return &c;
    return nullptr;
  }
  const ClassInfo* findName(const std::string& name) const {
    for (const ClassInfo& c : classes)
      if (c.name == name) return &c;
    return nullptr;
  }
  bool empty() const { return classes.empty(); }
};

}  // namespace vf
