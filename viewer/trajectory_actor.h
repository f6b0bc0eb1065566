#pragma once
// The camera path as a polyline through the camera centres, with a small wireframe frustum every
// few frames showing where each camera looked. VTK header: viewer/*.cpp only.
#include <vtkActor.h>
#include <vtkSmartPointer.h>

#include "core/pose.h"
#include "viewer/view_options.h"
#include "viewer/view_style.h"

namespace vf::viewer {

#include <vector>

// The path through all poses (with_path), and a frustum of depth_m and the camera's field of
// view at each of `frustum_poses` (frustumPoses()). The viewer makes one actor of each, so that
// the frusta can be hidden alone.
vtkSmartPointer<vtkActor> makeTrajectoryActor(const Trajectory& trajectory, bool with_path,
                                              const std::vector<size_t>& frustum_poses, double depth_m,
                                              const FrameCamera& camera);

}  // namespace vf::viewer
