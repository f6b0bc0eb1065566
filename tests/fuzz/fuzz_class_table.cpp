// Fuzz target: class table JSON (all three accepted forms), and its round trip.
#include "core/error.h"
#include "io/class_table_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  vf::ClassTable table;
  try {
    table = vf::parseClassTable(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json");
  } catch (const vf::Error&) {
    return 0;
  }
  // A table that parsed must write and read back to the same classes.
  const vf::ClassTable again = vf::parseClassTable(vf::classTableToJson(table), "roundtrip.json");
  if (again.classes.size() != table.classes.size()) std::abort();
  for (size_t i = 0; i < table.classes.size(); ++i)
    if (again.classes[i].id != table.classes[i].id || again.classes[i].name != table.classes[i].name) std::abort();
  return 0;
}
