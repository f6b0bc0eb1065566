#pragma once
// Which paths a command may write, decided before any work starts, the same way for every
// command: an existing output is kept unless --force is given, no output may be one of the
// command's inputs, sit inside an input folder, or (for a folder output) hold an input, no two
// outputs may be the same file, and an output's folder must exist. A claimed output is locked
// for the rest of the run (core/output_lock.h): a second run writing it fails at once. Then the
// temporaries a killed run left beside it are removed. The writes themselves go through
// core/atomic_output.h.
#include <filesystem>
#include <string>
#include <vector>

namespace vf::app {

class OutputPolicy {
 public:
  explicit OutputPolicy(bool force) : force_(force) {}

  // A file or folder the command reads.
  void input(const std::string& path);
  // Claims an output file; `option` names it in messages ("-o", "--trajectory"). Throws vf::Error.
  void file(const std::string& path, const std::string& option);
  // Claims an output folder, replaced as a whole when the command commits it.
  void folder(const std::string& path, const std::string& option);
  // A folder the command adds files to (--renders): only the input rules apply (neither locked
  // nor replaced; it may not exist yet).
  void filesInto(const std::string& path, const std::string& option);
  // Throws vf::Error unless `path` ends in one of `extensions` (".vdb"; any case), so that a file
  // is never written in a format its name does not say.
  static void requireExtension(const std::string& path, const std::vector<std::string>& extensions,
                               const std::string& option);

 private:
  struct Input {
    std::filesystem::path resolved;
    std::string given;  // as the user wrote it, for messages
  };
  void claim(const std::string& path, const std::string& option, bool is_folder);
  void refuseInsideInputs(const std::string& path, const std::filesystem::path& target, const std::string& option) const;
  bool force_;
  std::vector<Input> inputs_;
  std::vector<std::pair<std::filesystem::path, std::string>> outputs_;
};

}  // namespace vf::app
