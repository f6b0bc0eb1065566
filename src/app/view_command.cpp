// vdbfuse view: runs the vdbfuse-view executable installed beside vdbfuse, passing every argument
// through. The viewer is a separate program on purpose: linking VTK (some forty shared libraries,
// X11 and OpenGL) into vdbfuse would slow the start of every command and make the command line
// need a display stack on machines that only fuse and export; the viewer stays optional
// (-DVDBFUSE_WITH_VIEWER=OFF) and this command then says how to get it.
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/command_registry.h"
#include "app/run_control.h"
#include "core/error.h"

namespace vf::app {
namespace {

namespace fs = std::filesystem;

// vdbfuse-view beside this executable (build tree and install both put it there), else on PATH.
std::string findViewer() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path beside = self.parent_path() / "vdbfuse-view";
    if (fs::exists(beside)) return beside.string();
  }
  return "vdbfuse-view";  // execvp searches PATH
}

[[noreturn]] void runView(const std::vector<std::string>& args) {
  const std::string viewer = findViewer();
  std::vector<std::string> argv_strings{viewer};
  argv_strings.insert(argv_strings.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_strings) argv.push_back(a.data());
  argv.push_back(nullptr);
  restoreSignalMask();  // the viewer handles its own signals; exec keeps the mask
  execvp(viewer.c_str(), argv.data());
  const int err = errno;  // only reached when the exec failed
  throw Error("cannot run " + viewer + " (" + std::strerror(err) +
              "): vdbfuse view needs the vdbfuse-view executable beside vdbfuse or on PATH; build it with "
              "-DVDBFUSE_WITH_VIEWER=ON (needs libvtk9-dev)");
}

void setupViewCommand(CLI::App& root) {
  CLI::App* cmd = root.add_subcommand(
      "view", "Look at a scene in the VTK viewer (runs vdbfuse-view; `vdbfuse view --help` lists its options)");
  // Everything after `view`, --help included, belongs to vdbfuse-view.
  cmd->prefix_command();
  cmd->set_help_flag();
  cmd->allow_extras();
  cmd->callback([cmd] { runView(cmd->remaining()); });
}

}  // namespace

VF_REGISTER_COMMAND(45, setupViewCommand);

}  // namespace vf::app
