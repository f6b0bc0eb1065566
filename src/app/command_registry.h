#pragma once
// Subcommands register themselves, one file per command, so commands can be added without
// touching main.cpp. A command's callback parses nothing itself beyond CLI11's options, calls the
// library and reports; errors are thrown as vf::Error and turned into exit codes by main().
#include <CLI/CLI.hpp>

#include <functional>
#include <string>

namespace vf::app {

using CommandSetup = std::function<void(CLI::App& root)>;

struct CommandRegistrar {
  // order: position in --help (lower first).
  CommandRegistrar(int order, CommandSetup setup);
};

void setupAllCommands(CLI::App& root);

}  // namespace vf::app

#define VF_CONCAT_INNER(a, b) a##b
#define VF_CONCAT(a, b) VF_CONCAT_INNER(a, b)
#define VF_REGISTER_COMMAND(order, setup_fn) \
  static ::vf::app::CommandRegistrar VF_CONCAT(vf_command_registrar_, __COUNTER__)(order, setup_fn)
