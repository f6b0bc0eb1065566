// Configure-time check (src/vdb/CMakeLists.txt): links only if libopenvdb exports the members of
// Grid<T> and Tree<T> that vdb/openvdb_extern_grids.h declares extern, as this build's flags
// leave them to be called (a Debug build inlines nothing and fails: it compiles its own).
#include "vdb/openvdb_extern_grids.h"

#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>
#include <sstream>

template <typename GridT>
openvdb::GridBase::Ptr exercise(typename GridT::ValueType value) {
  typename GridT::Ptr grid = GridT::create(value);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(0.01));
  grid->tree().setValue(openvdb::Coord(1, 2, 3), value);
  grid->getAccessor().setValueOn(openvdb::Coord(9, 9, 9));
  grid->tree().prune();
  grid->pruneGrid();
  std::ostringstream text;
  grid->print(text, 3);
  (void)grid->activeVoxelCount();
  (void)grid->evalActiveVoxelBoundingBox();
  (void)grid->memUsage();
  (void)grid->tree().leafCount();
  openvdb::GridBase::Ptr copy = grid->deepCopyGrid();
  (void)grid->copyGrid();
  return copy;
}

int main() {
  openvdb::initialize();
  openvdb::GridPtrVec grids{exercise<openvdb::FloatGrid>(1.f), exercise<openvdb::Vec3SGrid>(openvdb::Vec3s(1.f)),
                            exercise<openvdb::Int32Grid>(1), exercise<openvdb::MaskGrid>(true)};
  std::ostringstream out;
  openvdb::io::Stream(out).write(grids);
  std::istringstream in(out.str());
  openvdb::GridPtrVecPtr back = openvdb::io::Stream(in).getGrids();
  return back && back->size() == grids.size() ? 0 : 1;
}
