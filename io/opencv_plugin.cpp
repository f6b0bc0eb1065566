#include "io/opencv_plugin.h"

#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>

#include "core/error.h"

namespace vf {
namespace fs = std::filesystem;

namespace {

constexpr const char* kModuleName = "libvdbfuse_opencv.so";

std::vector<fs::path> moduleFolders() {
  std::vector<fs::path> folders;
  if (const char* dir = std::getenv("VDBFUSE_PLUGIN_DIR"); dir && *dir) folders.emplace_back(dir);
  std::error_code ec;
  const fs::path program = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    folders.push_back(program.parent_path().parent_path() / "lib" / "vdbfuse");  // installed: bin/, lib/vdbfuse/
    folders.push_back(program.parent_path());
  }
#ifdef VDBFUSE_PLUGIN_BUILD_DIR
  folders.emplace_back(VDBFUSE_PLUGIN_BUILD_DIR);  // this build tree, for its tests and programs
#endif
  return folders;
}

OpenCvPlugin* loadModule(std::string& why) {
  std::string looked;
  for (const fs::path& folder : moduleFolders()) {
    const fs::path path = folder / kModuleName;
    looked += (looked.empty() ? "" : ", ") + path.string();
    std::error_code ec;
    if (!fs::exists(path, ec)) continue;
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);  // kept open for the process
    if (!handle) {
      why = "cannot load " + path.string() + ": " + dlerror();
      return nullptr;
    }
    auto entry = reinterpret_cast<OpenCvPlugin* (*)()>(dlsym(handle, VF_OPENCV_PLUGIN_ENTRY));
    if (!entry) {
      why = path.string() + " is from another vdbfuse build (no " VF_OPENCV_PLUGIN_ENTRY ")";
      return nullptr;
    }
    return entry();
  }
  why = std::string(kModuleName) + " not found (looked for " + looked + ")";
  return nullptr;
}

}  // namespace

OpenCvPlugin& openCvPlugin(const std::string& feature) {
  static std::once_flag once;
  static OpenCvPlugin* plugin = nullptr;
  static std::string why;
  std::call_once(once, [] { plugin = loadModule(why); });
  if (!plugin) throw Error(feature + " needs vdbfuse's OpenCV module: " + why);
  return *plugin;
}

}  // namespace vf
