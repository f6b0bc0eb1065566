#include "io/class_table_io.h"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/mapped_file.h"
#include "io/image_io.h"

namespace vf {
namespace {

using nlohmann::json;

int parseId(const json& value, const std::string& where) {
  if (!value.is_number_integer())
    throw Error(where + ": id must be an integer, got " + value.dump());
  const long long id = value.get<long long>();
  if (id < 0 || id > kMaxClassId)
    throw Error(where + ": id " + std::to_string(id) + " is outside 0.." + std::to_string(kMaxClassId));
  return int(id);
}

int parseKeyId(const std::string& key, const std::string& source) {
  size_t used = 0;
  long long id = -1;
  try {
    id = std::stoll(key, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != key.size() || key.empty() || id < 0 || id > kMaxClassId)
    throw Error(source + ": key '" + key + "' is not a class id (integer 0.." + std::to_string(kMaxClassId) + ")");
  return int(id);
}

Rgb8 parseColor(const json& value, const std::string& where) {
  if (!value.is_array() || value.size() != 3)
    throw Error(where + ": color must be [r, g, b], got " + value.dump());
  uint8_t c[3];
  for (int i = 0; i < 3; ++i) {
    if (!value[size_t(i)].is_number_integer() || value[size_t(i)].get<long long>() < 0 ||
        value[size_t(i)].get<long long>() > 255)
      throw Error(where + ": color components must be integers 0..255, got " + value.dump());
    c[i] = uint8_t(value[size_t(i)].get<int>());
  }
  return {c[0], c[1], c[2], 255};
}

std::string parseName(const json& value, const std::string& where) {
  if (!value.is_string() || value.get<std::string>().empty())
    throw Error(where + ": name must be a non-empty string, got " + value.dump());
  return value.get<std::string>();
}

void parseList(const json& list, const std::string& source, ClassTable& table) {
  for (size_t i = 0; i < list.size(); ++i) {
    const json& e = list[i];
    const std::string where = source + ": entry " + std::to_string(i);
    if (!e.is_object()) throw Error(where + ": expected {\"id\": .., \"name\": .., \"color\": [r, g, b]}");
    if (!e.contains("id") || !e.contains("name")) throw Error(where + ": needs \"id\" and \"name\"");
    ClassInfo c;
    c.id = parseId(e["id"], where);
    c.name = parseName(e["name"], where);
    c.color = e.contains("color") ? parseColor(e["color"], where) : paletteColor(c.id);
    table.classes.push_back(c);
  }
}

}  // namespace

Rgb8 paletteColor(int id) {
  // PASCAL VOC: bits 0,1,2 of the id go to the top bits of r,g,b, the next three to the next...
  int r = 0, g = 0, b = 0;
  for (int shift = 7, c = id; shift >= 0 && c; --shift, c >>= 3) {
    r |= ((c >> 0) & 1) << shift;
    g |= ((c >> 1) & 1) << shift;
    b |= ((c >> 2) & 1) << shift;
  }
  return {uint8_t(r), uint8_t(g), uint8_t(b), 255};
}

ClassTable parseClassTable(const std::string& json_text, const std::string& source) {
  json doc;
  std::set<std::string> top_keys;
  std::string duplicate_key;
  // nlohmann keeps the last of two equal keys silently; {"1": "a", "1": "b"} must be an error.
  const json::parser_callback_t find_duplicates = [&](int depth, json::parse_event_t event, json& parsed) {
    if (event == json::parse_event_t::key && depth == 1 && !top_keys.insert(parsed.get<std::string>()).second)
      duplicate_key = parsed.get<std::string>();
    return true;
  };
  try {
    doc = json::parse(json_text, find_duplicates);
  } catch (const json::exception& e) {  // parse_error, and out_of_range for numbers like 4e33336
    throw Error(source + ": not valid JSON (" + e.what() + ")");
  }
  if (!duplicate_key.empty()) throw Error(source + ": key '" + duplicate_key + "' appears twice");
  ClassTable table;
  if (doc.is_array()) {
    parseList(doc, source, table);
  } else if (doc.is_object() && doc.contains("classes") && doc["classes"].is_array()) {
    parseList(doc["classes"], source, table);
  } else if (doc.is_object()) {
    for (const auto& [key, value] : doc.items()) {
      ClassInfo c;
      c.id = parseKeyId(key, source);
      c.name = parseName(value, source + ": class " + key);
      c.color = paletteColor(c.id);
      table.classes.push_back(c);
    }
  } else {
    throw Error(source + ": expected a list of classes or an object {\"id\": \"name\"}");
  }
  if (table.empty()) throw Error(source + ": the class table is empty");

  std::sort(table.classes.begin(), table.classes.end(),
            [](const ClassInfo& a, const ClassInfo& b) { return a.id < b.id; });
  table.requireUnique(source);
  return table;
}

ClassTable readClassTable(const std::string& path) {
  // Far above the 150 classes of ADE20K (a few kB).
  return parseClassTable(readRegularFile(path, "class table", size_t(16) << 20), path);
}

std::string classTableToJson(const ClassTable& table) {
  std::vector<ClassInfo> sorted = table.classes;
  std::sort(sorted.begin(), sorted.end(), [](const ClassInfo& a, const ClassInfo& b) { return a.id < b.id; });
  // One class per line: diffable and readable, unlike json::dump(2) which splits every colour.
  std::string out = "[\n";
  for (size_t i = 0; i < sorted.size(); ++i) {
    const ClassInfo& c = sorted[i];
    out += "  {\"id\": " + std::to_string(c.id) + ", \"name\": " + json(c.name).dump() + ", \"color\": [" +
           std::to_string(c.color.r) + ", " + std::to_string(c.color.g) + ", " + std::to_string(c.color.b) + "]}" +
           (i + 1 < sorted.size() ? ",\n" : "\n");
  }
  return out + "]\n";
}

void writeClassTable(const std::string& path, const ClassTable& table) {
  writeFileAtomic(path, classTableToJson(table));
}

}  // namespace vf
