// vdbfuse: RGB-D sequences to clean, editable 3D scenes. Subcommands live in *_command.cpp.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>
#include <string>

#include "app/command_registry.h"
#include "app/field_flags.h"
#include "app/memory_check.h"
#include "app/run_control.h"
#include "app/usage_errors.h"
#include "core/error.h"
#include "core/version.h"

namespace {

// Runs the command line; returns main's status after reporting any error.
int runCommandLine(CLI::App& app, int argc, char** argv) {
  const auto report = [](const char* kind, const std::string& what) {
    vf::app::awaitSignalTermination();  // a failure caused by a signal's cleanup is not reported
    std::fprintf(stderr, "vdbfuse: %s: %s\n", kind, what.c_str());
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return vf::app::reportParseError(app, e, "vdbfuse");
  } catch (const vf::app::ExitWithStatus& e) {
    return e.status;  // the command already said why
  } catch (const vf::Error& e) {
    report("error", vf::app::withOptionNames(e.what()));
    return 1;
  } catch (const std::filesystem::filesystem_error& e) {
    // A file operation the command did not expect to fail (read-only folder, vanished file).
    report("error", e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    const std::vector<CLI::App*> parsed = app.get_subcommands();
    report("error", vf::app::outOfMemoryMessage(parsed.empty() ? "" : parsed.front()->get_name()));
    return 1;
  } catch (const std::exception& e) {
    report("internal error", e.what());
    return 2;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  vf::app::startSignalThread();  // before any other thread exists (see run_control.h)
  CLI::App app{"vdbfuse " VDBFUSE_VERSION_STRING
               ": fuse RGB-D sequences into OpenVDB scenes, edit them and export meshes"};
  app.set_version_flag("--version", VDBFUSE_VERSION_STRING);
  app.require_subcommand(1);
  vf::app::setupAllCommands(app);
  vf::app::requireFiniteNumbers(app);  // every float option of every command, reconstruct's too
  const int status = runCommandLine(app, argc, argv);
  vf::app::awaitSignalTermination();  // a signal that came while the command ended decides the status
  return status;
}
