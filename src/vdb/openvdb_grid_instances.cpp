// The explicit instantiations that vdb/openvdb_extern_grids.h declares, for a libopenvdb that
// does not export them (src/vdb/CMakeLists.txt compiles this file only then): every other file
// of vf_vdb then links against these instead of compiling the classes itself.
#include "vdb/openvdb_extern_grids.h"

#define VF_INSTANTIATE_GRID_AND_TREE(TreeT) \
  template class openvdb::Grid<TreeT>;         \
  template class openvdb::tree::Tree<TreeT::RootNodeType>;
VF_FOR_EACH_SCENE_TREE(VF_INSTANTIATE_GRID_AND_TREE)
#undef VF_INSTANTIATE_GRID_AND_TREE
