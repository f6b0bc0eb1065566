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

  // The ids of the classes named in `items`: each is a class name or a numeric id, and
  // comma-separated lists are split (blanks trimmed). Ids come in the order first named, each
  // once. Throws vf::Error starting with `what` for an unknown name or id, or when no class is
  // given, listing the valid ones.
  std::vector<int> resolve(const std::vector<std::string>& items, const std::string& what) const;
  // "person (1), chair (2)", or a note that the table is empty: for messages.
  std::string listing() const;
  // Throws vf::Error starting with `source` when two classes share an id or a name, or a name is
  // empty: a label would then mean two classes, and the faces of one land in the other's mesh.
  // Every table read from outside (a class table file, a scene's metadata) goes through it.
  void requireUnique(const std::string& source) const;
};

}  // namespace vf
