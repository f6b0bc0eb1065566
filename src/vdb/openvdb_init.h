#pragma once
// Kept apart from vdb/scene_grids.h so that code needing only OpenVDB's registries (metadata and
// grid types) does not compile the whole of openvdb/openvdb.h.

namespace vf {

// Makes sure openvdb::initialize() ran (idempotent, thread-safe).
void ensureOpenVdbInitialized();

}  // namespace vf
