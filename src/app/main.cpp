// vdbfuse: RGB-D sequences to clean, editable 3D scenes. Subcommands live in *_command.cpp.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "app/command_registry.h"
#include "app/run_control.h"
#include "core/error.h"
#include "core/version.h"

int main(int argc, char** argv) {
  CLI::App app{"vdbfuse " VDBFUSE_VERSION_STRING
               ": fuse RGB-D sequences into OpenVDB scenes, edit them and export meshes"};
  app.set_version_flag("--version", VDBFUSE_VERSION_STRING);
  app.require_subcommand(1);
  vf::app::setupAllCommands(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const vf::app::ExitWithStatus& e) {
    return e.status;  // the command already said why
  } catch (const vf::Error& e) {
    std::fprintf(stderr, "vdbfuse: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vdbfuse: internal error: %s\n", e.what());
    return 2;
  }
  return 0;
}
