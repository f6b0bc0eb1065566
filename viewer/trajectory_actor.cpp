#include "viewer/trajectory_actor.h"

#include <vtkCellArray.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>

#include <cmath>

namespace vf::viewer {
namespace {

vtkIdType addPoint(vtkPoints* points, const Eigen::Vector3d& p) { return points->InsertNextPoint(p.x(), p.y(), p.z()); }

void addLine(vtkCellArray* lines, vtkIdType a, vtkIdType b) {
  const vtkIdType ids[2] = {a, b};
  lines->InsertNextCell(2, ids);
}

// Apex at the camera centre, the image rectangle at depth_m along the camera's +z (y down), and
// a small tick on the top edge's middle so that "up" reads in the picture.
void addFrustum(vtkPoints* points, vtkCellArray* lines, const Pose& T_world_cam, double depth_m,
                const FrameCamera& camera) {
  const double half_h = depth_m * std::tan(0.5 * camera.fov_y_deg * M_PI / 180.0), half_w = half_h * camera.aspect;
  const vtkIdType apex = addPoint(points, T_world_cam.translation());
  vtkIdType corner[4];
  const double cx[4] = {-half_w, half_w, half_w, -half_w}, cy[4] = {-half_h, -half_h, half_h, half_h};
  for (int k = 0; k < 4; ++k) corner[k] = addPoint(points, T_world_cam * Eigen::Vector3d(cx[k], cy[k], depth_m));
  for (int k = 0; k < 4; ++k) {
    addLine(lines, apex, corner[k]);
    addLine(lines, corner[k], corner[(k + 1) % 4]);
  }
  const vtkIdType tip = addPoint(points, T_world_cam * Eigen::Vector3d(0, -1.4 * half_h, depth_m));
  addLine(lines, corner[0], tip);
  addLine(lines, tip, corner[1]);
}

}  // namespace

vtkSmartPointer<vtkActor> makeTrajectoryActor(const Trajectory& trajectory, bool with_path,
                                              const std::vector<size_t>& frustum_poses, double depth_m,
                                              const FrameCamera& camera) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  auto lines = vtkSmartPointer<vtkCellArray>::New();
  const vtkIdType n = vtkIdType(trajectory.size());
  if (with_path && n >= 2) {
    lines->InsertNextCell(n);
    for (const StampedPose& p : trajectory) lines->InsertCellPoint(addPoint(points, p.T_world_cam.translation()));
  }
  for (size_t i : frustum_poses) addFrustum(points, lines, trajectory[i].T_world_cam, depth_m, camera);

  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetLines(lines);
  auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  mapper->SetInputData(poly);
  mapper->ScalarVisibilityOff();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  vtkProperty* prop = actor->GetProperty();
  prop->SetColor(kTrajectoryColor[0] / 255.0, kTrajectoryColor[1] / 255.0, kTrajectoryColor[2] / 255.0);
  prop->SetLineWidth(2.0);
  prop->LightingOff();  // lines keep their color whatever the lights
  actor->PickableOff();
  return actor;
}

}  // namespace vf::viewer
