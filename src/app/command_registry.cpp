#include "app/command_registry.h"

#include <algorithm>
#include <vector>

namespace vf::app {
namespace {

struct Entry {
  int order;
  CommandSetup setup;
};
std::vector<Entry>& registry() {
  static std::vector<Entry> entries;
  return entries;
}

}  // namespace

CommandRegistrar::CommandRegistrar(int order, CommandSetup setup) {
  registry().push_back({order, std::move(setup)});
}

void setupAllCommands(CLI::App& root) {
  auto entries = registry();
  std::stable_sort(entries.begin(), entries.end(),
                   [](const Entry& a, const Entry& b) { return a.order < b.order; });
  for (const Entry& e : entries) e.setup(root);
}

}  // namespace vf::app
