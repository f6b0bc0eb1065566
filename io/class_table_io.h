#pragma once
// Class tables (id -> name, colour) as JSON. Accepted forms:
//   [{"id": 0, "name": "wall", "color": [r, g, b]}, ...]        colour optional
//   {"classes": [ ...same list... ], "description": "..."}      list plus free-form metadata
//   {"0": "background", "1": "person"}                          ids as keys, names as values
// Missing colours come from paletteColor(id), so a table always has distinct display colours.
#include <string>

#include "core/error.h"
#include "core/class_table.h"

namespace vf {

// Largest class id a table may hold: label maps are uint16 and 0xFFFF means "unknown" in the
// fusion volume (kUnknownClass).
constexpr int kMaxClassId = 0xFFFE;

// Throws vf::Error naming the file for unreadable JSON, duplicate ids or names, empty names,
// ids out of [0, kMaxClassId] or colours that are not three integers in 0..255.
ClassTable readClassTable(const std::string& path);
// Same, from JSON text; `source` names it in error messages. Classes come out sorted by id.
ClassTable parseClassTable(const std::string& json_text, const std::string& source);

// Writes the list form, sorted by id, atomically (temp file + rename).
void writeClassTable(const std::string& path, const ClassTable& table);
std::string classTableToJson(const ClassTable& table);

// Fixed distinct colour per id: the PASCAL VOC colour map (bit-interleaved id), distinct for
// every id below 2^24; id 0 is black.
Rgb8 paletteColor(int id);

}  // namespace vf
