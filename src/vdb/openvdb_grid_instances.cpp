// The explicit instantiations that vdb/openvdb_extern_grids.h declares, for a libopenvdb that
// does not export them (src/vdb/CMakeLists.txt compiles this file only then): every other file
// of vf_vdb then links against these instead of compiling the classes itself.
#include "vdb/openvdb_extern_grids.h"

template class openvdb::Grid<openvdb::FloatTree>;
template class openvdb::Grid<openvdb::Vec3STree>;
template class openvdb::Grid<openvdb::Int32Tree>;
template class openvdb::Grid<openvdb::MaskTree>;
template class openvdb::tree::Tree<openvdb::FloatTree::RootNodeType>;
template class openvdb::tree::Tree<openvdb::Vec3STree::RootNodeType>;
template class openvdb::tree::Tree<openvdb::Int32Tree::RootNodeType>;
template class openvdb::tree::Tree<openvdb::MaskTree::RootNodeType>;
