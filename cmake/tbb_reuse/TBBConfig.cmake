# Stand-in for TBB's CMake package while VTK looks for TBB (viewer/CMakeLists.txt, src/slam/CMakeLists.txt: VTK and Ceres).
# The top level already made TBB::tbb with OpenVDB's FindTBB; TBB's own TBBConfig.cmake then
# refuses to load ("Some (but not all) targets in this export set were already defined").
# VTK only needs TBB::tbb to exist, so reuse it; without it, defer to the real package.
if(TARGET TBB::tbb)
  set(TBB_FOUND TRUE)
  set(TBB_tbb_FOUND TRUE)
  set(TBB_VERSION "${TBB_VERSION}")
else()
  include(/usr/lib/x86_64-linux-gnu/cmake/TBB/TBBConfig.cmake)
endif()
