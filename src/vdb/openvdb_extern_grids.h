#pragma once
// The Grid and Tree classes of the scene's grids are compiled once, not in every file that uses
// them: declared extern here, they come from libopenvdb (Debian's build exports the vtables and
// members of Grid<T> and Tree<T> for the standard trees) or, where a configure-time check finds
// the library lacking, from vdb/openvdb_grid_instances.cpp (src/vdb/CMakeLists.txt). Without
// this each file instantiated every virtual member again (readBuffers, print, copyGrid, ... and
// the tree I/O behind them): scene_stream_writer.cpp took 65 s to compile, 19 s with it.
#include <openvdb/openvdb.h>

extern template class openvdb::Grid<openvdb::FloatTree>;
extern template class openvdb::Grid<openvdb::Vec3STree>;
extern template class openvdb::Grid<openvdb::Int32Tree>;
extern template class openvdb::Grid<openvdb::MaskTree>;
extern template class openvdb::tree::Tree<openvdb::FloatTree::RootNodeType>;
extern template class openvdb::tree::Tree<openvdb::Vec3STree::RootNodeType>;
extern template class openvdb::tree::Tree<openvdb::Int32Tree::RootNodeType>;
extern template class openvdb::tree::Tree<openvdb::MaskTree::RootNodeType>;
