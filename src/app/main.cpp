// vdbfuse: RGB-D sequences to clean, editable 3D scenes. Subcommands live in *_command.cpp.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>

#include "app/command_registry.h"
#include "app/field_flags.h"
#include "app/run_control.h"
#include "core/error.h"
#include "core/version.h"

int main(int argc, char** argv) {
  vf::app::startSignalThread();  // before any other thread exists (see run_control.h)
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
    std::fprintf(stderr, "vdbfuse: error: %s\n", vf::app::withOptionNames(e.what()).c_str());
    return 1;
  } catch (const std::filesystem::filesystem_error& e) {
    // A file operation the command did not expect to fail (read-only folder, vanished file).
    std::fprintf(stderr, "vdbfuse: error: %s\n", e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "vdbfuse: error: out of memory (an input states sizes this machine cannot hold)\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vdbfuse: internal error: %s\n", e.what());
    return 2;
  }
  return 0;
}
