#pragma once
#include <stdexcept>
#include <string>

namespace vf {

// The one exception type of the project. The message says what went wrong and, where it can,
// which file, field or option to change. Only src/app and viewer print it and choose exit codes.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace vf
