#pragma once
// The library names what is wrong by its parameter field ("VolumeSpec.voxel_size_m = -1: ...");
// the command line user knows the option. This one table maps fields to options for messages.
#include <string>

namespace vf::app {

// `message` with every known field name followed by the option that sets it:
// "VolumeSpec.voxel_size_m (--voxel-size-m) = -1: ...".
std::string withOptionNames(const std::string& message);

}  // namespace vf::app
