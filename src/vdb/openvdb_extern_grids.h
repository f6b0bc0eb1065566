#pragma once
// The Grid and Tree classes of the scene's grids are compiled once, not in every file that uses
// them: declared extern here, they come from libopenvdb (Debian's build exports the vtables and
// members of Grid<T> and Tree<T> for the standard trees) or, where a configure-time check finds
// the library lacking, from vdb/openvdb_grid_instances.cpp (src/vdb/CMakeLists.txt). Without
// this each file instantiated every virtual member again (readBuffers, print, copyGrid, ... and
// the tree I/O behind them): scene_stream_writer.cpp took 65 s to compile, 19 s with it.
#include <openvdb/openvdb.h>

// The trees of the scene's grids, for the declarations here and the definitions in
// openvdb_grid_instances.cpp: one list, so that the two cannot drift apart.
#define VF_FOR_EACH_SCENE_TREE(X) X(openvdb::FloatTree) X(openvdb::Vec3STree) X(openvdb::Int32Tree) X(openvdb::MaskTree)

#define VF_EXTERN_GRID_AND_TREE(TreeT) \
  extern template class openvdb::Grid<TreeT>;  \
  extern template class openvdb::tree::Tree<TreeT::RootNodeType>;
VF_FOR_EACH_SCENE_TREE(VF_EXTERN_GRID_AND_TREE)
#undef VF_EXTERN_GRID_AND_TREE
