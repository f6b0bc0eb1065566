#include "viewer/scene_view.h"

#include <vtkActor.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCoordinate.h>
#include <vtkImageData.h>
#include <vtkLightKit.h>
#include <vtkNew.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>
#include <vtkPlane.h>
#include <vtkPointData.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "core/error.h"
#include "io/image_io.h"
#include "io/mesh_io.h"
#include "vdb/scene_frame.h"
#include "viewer/class_panel.h"
#include "viewer/frustum_poses.h"
#include "viewer/interaction.h"
#include "viewer/slice_actor.h"
#include "viewer/trajectory_actor.h"
#include "viewer/view_style.h"
#include "viewer/vtk_mesh.h"

namespace vf::viewer {
namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

const char* kHelp =
    "mouse    left drag: rotate   middle: pan   right / wheel: zoom\n"
    "h        show / hide this help\n"
    "c        color: fused RGB  <->  class colors\n"
    "1 .. 9   show / hide that class (or click it in the panel)\n"
    "0        show all classes\n"
    "f  t  v  camera: front (as the first frame, level) / top / side\n"
    "n        camera: next trajectory frustum\n"
    "p  k     trajectory path / camera frusta on / off\n"
    "m        surface on / off      b: back faces on / off\n"
    "l        floor plan: level slice 1 m above the floor  (again: hide)\n"
    "x y z    slice across world x / y / z  (same key again: hide)\n"
    "[  ]     move the slice one voxel   ({  }: ten voxels)\n"
    "g        slice grid: tsdf  <->  weight\n"
    "s        save a screenshot PNG next to the scene\n"
    "e        export the visible classes to <scene>_visible.ply\n"
    "q  Esc   quit";

// Places the camera looking along `dir` (with `up` up) at the centre of `corners`, just far
// enough that every corner is inside the view: tighter than VTK's ResetCamera, which fits the
// bounding sphere and leaves a flat scene small in the middle.
void fitView(vtkCamera* cam, const Vec3f& dir, const Vec3f& up, const std::vector<Vec3f>& corners, double fov_y_deg,
             double aspect) {
  Vec3f c{0, 0, 0};
  for (const Vec3f& p : corners) c = c + p * (1.f / float(corners.size()));
  const Vec3f right = cross(dir, up);
  const double tan_y = std::tan(0.5 * fov_y_deg * M_PI / 180.0), tan_x = tan_y * aspect;
  double distance = 0;
  for (const Vec3f& corner : corners) {
    const Vec3f p = corner - c;
    const double x = dot(p, right), y = dot(p, up), z = dot(p, dir);
    // The corner at depth (distance + z) in front of the eye must satisfy |x| <= depth tan_x.
    distance = std::max(distance, std::max(std::abs(x) / tan_x, std::abs(y) / tan_y) - z);
  }
  distance = std::max(distance * 1.05, 1e-3);  // a small margin around the surface
  cam->SetFocalPoint(c.x, c.y, c.z);
  cam->SetPosition(c.x - distance * dir.x, c.y - distance * dir.y, c.z - distance * dir.z);
  cam->SetViewUp(up.x, up.y, up.z);
  cam->SetViewAngle(fov_y_deg);
}

// The 8 corners of a box given in level-frame coordinates, in world coordinates.
std::vector<Vec3f> frameBoxCorners(const LevelFrame& f, Vec3f lo, Vec3f hi) {
  std::vector<Vec3f> corners;
  for (int k = 0; k < 8; ++k) corners.push_back(f.toWorld({k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z}));
  return corners;
}

std::string vectorText(const double v[3]) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "[%.4f %.4f %.4f]", v[0], v[1], v[2]);
  return buf;
}

void styleText(vtkTextActor* t, int font_px) {
  vtkTextProperty* p = t->GetTextProperty();
  p->SetFontSize(font_px);
  p->SetColor(1, 1, 1);
  p->ShadowOn();
  t->PickableOff();
}

}  // namespace

struct SceneView::Impl {
  SceneContent& content;
  ViewOptions options;
  bool offscreen;
  int font_px;

  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkRenderWindow> window;
  vtkRenderWindowInteractor* interactor = nullptr;
  std::vector<vtkSmartPointer<vtkPolyDataMapper>> part_mappers;
  std::vector<vtkSmartPointer<vtkActor>> part_actors;
  std::vector<bool> shown;  // per class row
  bool color_by_class = false;
  ClassPanel panel;
  vtkSmartPointer<vtkActor> trajectory_actor, frusta_actor;
  bool trajectory_shown = false, frusta_shown = false;
  bool surface_shown = true, backfaces_shown = false;
  vtkNew<vtkPlane> cut_plane;  // a floor plan cuts the surface above it away
  std::vector<size_t> frustum_poses;  // poses with a frustum: what 'n' steps through
  int camera_frame = -1;
  SliceActor slice_actor;
  SliceSpec slice;
  SliceImage slice_image;  // the slice shown (when slice.enabled)
  int slice_index = 0;
  bool slice_placed = false;  // slice_index holds a position the user has seen
  vtkNew<vtkTextActor> help_text, info_text, notice_text, hint_text;
  std::vector<std::string> notices;
  vtkNew<vtkCallbackCommand> layout_callback;
  double build_s = 0, first_render_s = -1;

  Impl(SceneContent& c, const ViewOptions& o, bool off) : content(c), options(o), offscreen(off) {
    font_px = std::clamp(options.height / 44, 12, 30);
  }

  void build();
  void buildSurface();
  void buildTrajectory();
  void buildOverlays();
  void applyColors();
  void applyVisibility();
  void applyTrajectoryVisibility();
  void applyCut();
  void setCamera(const CameraSpec& spec);
  void showSlice();
  void updateInfo();
  void say(const std::string& message);
  void render();
  ColorImage capture();
  void onKey(char key, const std::string& keysym);
  bool onClick(int x, int y);
  void toggleRow(int row);
  void setSliceAxis(int axis);
  void toggleLevelSlice();
  void moveSlice(int voxels);
  void exportVisible();
  void screenshotKey();
};

void SceneView::Impl::build() {
  const auto t0 = std::chrono::steady_clock::now();
  window->AddRenderer(renderer);
  window->SetSize(options.width, options.height);
  window->SetOffScreenRendering(offscreen ? 1 : 0);
  // Antialiasing by FXAA: a post-pass costing milliseconds, where 8x multisampling made the first
  // frame of a 512^3 scene 1-2 s slower under software OpenGL (Xvfb).
  window->SetMultiSamples(0);
  renderer->UseFXAAOn();
  window->SetWindowName(("vdbfuse-view - " + std::filesystem::path(content.scene_path).filename().string()).c_str());
  renderer->GradientBackgroundOn();
  renderer->SetBackground(kBackgroundBottom[0], kBackgroundBottom[1], kBackgroundBottom[2]);
  renderer->SetBackground2(kBackgroundTop[0], kBackgroundTop[1], kBackgroundTop[2]);
  // Key, fill, back and head lights, all following the camera: shape reads from any side.
  vtkNew<vtkLightKit> lights;
  lights->AddLightsToRenderer(renderer);

  buildSurface();
  buildTrajectory();
  buildOverlays();

  // Options that name classes / slices / poses: fail before any picture is made.
  for (const std::string& name : options.hide_classes) {
    if (content.rows.empty())
      throw Error("--hide-classes: the scene has no class grid (fused without labels), there is no class to hide");
    const int row = findClassRow(content.rows, name);
    if (row < 0) {
      std::string names;
      for (const ClassRow& r : content.rows) names += (names.empty() ? "" : ", ") + r.name;
      throw Error("--hide-classes: no class '" + name + "' in the scene; its classes are: " + names);
    }
    shown[size_t(row)] = false;
  }
  if (options.color_by_class) {
    if (content.rows.empty())
      say("class coloring: the scene has no class grid (fused without labels), showing RGB");
    else
      color_by_class = true;
  }
  if (options.slice.enabled) {
    slice = options.slice;
    if (slice.level)
      requireLevelInRange(content.summary, content.frame, slice.value_m);
    else
      slice_index = sliceIndexAt(content.scene, content.summary, slice.axis, slice.value_m);
    showSlice();
  }
  surface_shown = options.show_surface;
  applyColors();
  applyVisibility();
  CameraSpec camera = options.camera;
  if (!options.camera_given && slice.enabled)
    camera.preset = cameraFacingSlice(slice, content.frame.up, content.frame.forward);
  setCamera(camera);
  updateInfo();
  build_s = secondsSince(t0);
}

void SceneView::Impl::buildSurface() {
  for (const ClassPart& part : content.parts) {
    auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
    mapper->SetInputData(toPolyData(part.mesh, part.class_colors));
    mapper->SetScalarModeToUsePointFieldData();
    mapper->SetColorModeToDirectScalars();
    mapper->ScalarVisibilityOn();
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    vtkProperty* p = actor->GetProperty();
    p->SetAmbient(0.15);
    p->SetDiffuse(0.85);
    p->SetSpecular(0.08);
    p->SetSpecularPower(20);
    // The surface's faces point into the space the cameras saw (the room); seen from outside, a
    // wall's back face is culled, so that a view from beyond a wall looks into the room.
    p->BackfaceCullingOn();
    mapper->AddClippingPlane(cut_plane);
    renderer->AddActor(actor);
    part_mappers.push_back(mapper);
    part_actors.push_back(actor);
  }
  shown.assign(content.rows.size(), true);
  applyCut();
}

void SceneView::Impl::buildTrajectory() {
  if (content.trajectory.empty()) return;
  const Vec3f d = content.surface_max_m - content.surface_min_m;
  const double depth_m = std::max(0.02, 0.035 * double(norm(d)));  // small next to the scene
  frustum_poses = frustumPoses(content.trajectory, options.frustum_every, 1.5 * depth_m);
  const FrameCamera camera = frameCamera(content.scene.meta.depth_intrinsics);
  trajectory_actor = makeTrajectoryActor(content.trajectory, true, {}, depth_m, camera);
  frusta_actor = makeTrajectoryActor(content.trajectory, false, frustum_poses, depth_m, camera);
  renderer->AddActor(trajectory_actor);
  renderer->AddActor(frusta_actor);
  trajectory_shown = options.show_trajectory;
  frusta_shown = options.show_trajectory && (options.show_frusta || options.frustum_every > 0);
  applyTrajectoryVisibility();
}

// Path and frusta, unless the camera is a recorded one (whose own frustum would frame the picture).
void SceneView::Impl::applyTrajectoryVisibility() {
  if (!trajectory_actor) return;
  trajectory_actor->SetVisibility(trajectory_shown && camera_frame < 0);
  frusta_actor->SetVisibility(frusta_shown && camera_frame < 0);
}

// A floor plan cuts the surface above its plane away, so that the top view sees the plan and
// the walls' lower parts; any other slice (or none) leaves the surface whole.
void SceneView::Impl::applyCut() {
  const LevelFrame& f = content.frame;
  if (slice.enabled && slice.level) {
    const Vec3f at = f.up * float(f.floor_m + slice.value_m);
    cut_plane->SetOrigin(at.x, at.y, at.z);
    cut_plane->SetNormal(-f.up.x, -f.up.y, -f.up.z);  // VTK keeps the side the normal points to
  } else {
    // Far above everything: nothing is cut.
    const Vec3f at = f.up * (f.max.z + 1e3f);
    cut_plane->SetOrigin(at.x, at.y, at.z);
    cut_plane->SetNormal(-f.up.x, -f.up.y, -f.up.z);
  }
}

void SceneView::Impl::buildOverlays() {
  panel.build(renderer, content.rows, font_px);
  panel.setShown(std::vector<bool>(content.rows.size(), true));
  slice_actor.attach(renderer, font_px);

  styleText(info_text, font_px);
  info_text->SetPosition(font_px, font_px);
  renderer->AddActor2D(info_text);
  styleText(notice_text, font_px);
  notice_text->GetTextProperty()->SetColor(1.0, 0.86, 0.45);
  notice_text->SetPosition(font_px, font_px + int(1.7 * font_px));
  renderer->AddActor2D(notice_text);

  styleText(help_text, font_px);
  vtkTextProperty* hp = help_text->GetTextProperty();
  hp->SetFontFamilyToCourier();  // columns line up
  hp->SetJustificationToLeft();  // keys and their meanings in columns; centred by the layout
  hp->SetVerticalJustificationToCentered();
  hp->ShadowOff();
  hp->SetBackgroundColor(0.08, 0.09, 0.1);
  hp->SetBackgroundOpacity(0.85);
  hp->SetFrame(true);
  hp->SetFrameColor(0.6, 0.6, 0.6);
  hp->SetLineSpacing(1.25);
  help_text->SetInput(kHelp);
  help_text->SetLayerNumber(2);
  help_text->VisibilityOff();
  renderer->AddActor2D(help_text);

  if (!offscreen) {  // a picture does not need the hint, a window does
    styleText(hint_text, font_px);
    hint_text->GetTextProperty()->SetJustificationToRight();
    hint_text->GetTextProperty()->SetColor(0.85, 0.85, 0.85);
    hint_text->SetInput("h: help");
    hint_text->GetPositionCoordinate()->SetCoordinateSystemToDisplay();
    renderer->AddActor2D(hint_text);
  }
  // Overlays are laid out in pixels from the top left; redo it whenever the window size may
  // have changed (cheap: a few text extents).
  layout_callback->SetClientData(this);
  layout_callback->SetCallback([](vtkObject*, unsigned long, void* self, void*) {
    Impl* impl = static_cast<Impl*>(self);
    impl->panel.layout(impl->renderer);
    const int* size = impl->renderer->GetSize();
    impl->hint_text->SetPosition(size[0] - impl->font_px, impl->font_px);
    if (impl->help_text->GetVisibility()) {
      double box[4];
      impl->help_text->GetBoundingBox(impl->renderer, box);
      impl->help_text->SetPosition(0.5 * (size[0] - (box[1] - box[0])), 0.5 * size[1]);
    }
  });
  renderer->AddObserver(vtkCommand::StartEvent, layout_callback);
}

void SceneView::Impl::applyColors() {
  for (auto& m : part_mappers) m->SelectColorArray(color_by_class ? kClassArray : kRgbArray);
}

void SceneView::Impl::applyVisibility() {
  for (size_t i = 0; i < part_actors.size(); ++i) {
    part_actors[i]->SetVisibility(surface_shown && (content.rows.empty() || shown[i]));
    part_actors[i]->GetProperty()->SetBackfaceCulling(!backfaces_shown);
  }
  panel.setShown(shown);
}

void SceneView::Impl::setCamera(const CameraSpec& spec) {
  vtkCamera* cam = renderer->GetActiveCamera();
  const LevelFrame& frame = content.frame;
  Vec3f lo = frame.min, hi = frame.max;  // the surface's box in the level frame
  if (trajectory_actor && trajectory_shown) {  // the cameras belong in the picture too
    for (const StampedPose& p : content.trajectory) {
      const Eigen::Vector3d t = p.T_world_cam.translation();
      const Vec3f q = frame.toFrame({float(t.x()), float(t.y()), float(t.z())});
      lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
      hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
    }
  }
  if (spec.preset == CameraPreset::kTrajectory) {
    const Trajectory& traj = content.trajectory;
    if (traj.empty())
      throw Error("--camera trajectory:" + std::to_string(spec.frame) +
                  ": no trajectory is loaded (none beside the scene; name one with --trajectory FILE)");
    if (size_t(spec.frame) >= traj.size())
      throw Error("--camera trajectory:" + std::to_string(spec.frame) + ": the trajectory has " +
                  std::to_string(traj.size()) + " poses (0.." + std::to_string(traj.size() - 1) + ")");
    // Exactly the recorded camera: centre, +z forward, -y up.
    const Pose& T = traj[size_t(spec.frame)].T_world_cam;
    const Eigen::Vector3d eye = T.translation(), ahead = T * Eigen::Vector3d(0, 0, 1),
                          up = T.linear() * Eigen::Vector3d(0, -1, 0);
    cam->SetPosition(eye.x(), eye.y(), eye.z());
    cam->SetFocalPoint(ahead.x(), ahead.y(), ahead.z());
    cam->SetViewUp(up.x(), up.y(), up.z());
    // The recorded camera's field of view, fitted into the window: its vertical angle when the
    // window is wider than the image, else its horizontal one.
    const FrameCamera recorded = frameCamera(content.scene.meta.depth_intrinsics);
    const int* size = window->GetSize();
    const double window_aspect = size[1] > 0 ? double(size[0]) / size[1] : 1.0;
    const double tan_y = std::tan(0.5 * recorded.fov_y_deg * M_PI / 180.0);
    cam->SetUseHorizontalViewAngle(window_aspect < recorded.aspect);
    cam->SetViewAngle(window_aspect < recorded.aspect ? 2.0 * std::atan(tan_y * recorded.aspect) * 180.0 / M_PI
                                                      : recorded.fov_y_deg);
    // Seen from a recorded camera the frustums would frame the picture itself: hide the path
    // until the camera leaves the trajectory.
    camera_frame = spec.frame;
  } else {
    // Presets in the scene's level frame (level_frame.h): front level along the first camera's
    // heading, side turned about up, top down along -up.
    const PresetView view = presetView(frame, spec.preset);
    const int* size = window->GetSize();
    const double aspect = size[1] > 0 ? double(size[0]) / size[1] : 1.0;
    cam->SetUseHorizontalViewAngle(false);
    fitView(cam, view.direction, view.view_up, frameBoxCorners(frame, lo, hi), 30.0, aspect);
    camera_frame = -1;
  }
  applyTrajectoryVisibility();
  renderer->ResetCameraClippingRange();
}

void SceneView::Impl::showSlice() {
  if (slice.level) {
    const LevelRange r = levelSliceRange(content.summary, content.frame);
    slice.value_m = std::clamp(slice.value_m, r.lowest_m, r.highest_m);
    slice_image = sampleLevelSlice(content.scene, content.summary, content.frame, slice.grid, slice.value_m);
  } else {
    slice_image = sampleSlice(content.scene, content.summary, slice.grid, slice.axis, slice_index);
    slice_index = slice_image.index;
    slice.value_m = slice_image.value_m;
    slice_placed = true;
  }
  slice.enabled = true;
  slice_actor.show(slice_image);
  applyCut();
}

void SceneView::Impl::updateInfo() {
  char buf[512];
  std::snprintf(buf, sizeof buf, "%s    %s triangles    color: %s",
                std::filesystem::path(content.scene_path).filename().string().c_str(),
                withThousands(content.triangles).c_str(), color_by_class ? "class" : "rgb");
  std::string info = buf;
  if (slice.enabled && slice.level) {
    std::snprintf(buf, sizeof buf, "    floor plan %.2f m above the floor (%s)", slice.value_m,
                  slice.grid == SliceGrid::kTsdf ? "tsdf" : "weight");
    info += buf;
  } else if (slice.enabled) {
    std::snprintf(buf, sizeof buf, "    slice %s = %.3f m (%s)", axisName(slice.axis), slice.value_m,
                  slice.grid == SliceGrid::kTsdf ? "tsdf" : "weight");
    info += buf;
  }
  if (camera_frame >= 0) info += "    camera: frame " + std::to_string(camera_frame);
  info_text->SetInput(info.c_str());
}

void SceneView::Impl::say(const std::string& message) {
  notices.push_back(message);
  notice_text->SetInput(message.c_str());
  if (!offscreen) std::printf("%s\n", message.c_str());
}

void SceneView::Impl::render() {
  const auto t0 = std::chrono::steady_clock::now();
  window->Render();
  if (first_render_s < 0) first_render_s = secondsSince(t0);
}

ColorImage SceneView::Impl::capture() {
  render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->ShouldRerenderOff();
  grab->Update();
  vtkImageData* img = grab->GetOutput();
  int dims[3];
  img->GetDimensions(dims);
  auto* px = static_cast<unsigned char*>(img->GetScalarPointer());
  ColorImage out(dims[0], dims[1]);
  for (int y = 0; y < dims[1]; ++y)  // VTK rows go bottom up
    for (int x = 0; x < dims[0]; ++x) {
      const unsigned char* p = px + 3 * (size_t(dims[1] - 1 - y) * dims[0] + x);
      out(x, y) = Rgb8{p[0], p[1], p[2], 255};
    }
  return out;
}

void SceneView::Impl::toggleRow(int row) {
  if (row < 0 || row >= int(shown.size())) return;
  shown[size_t(row)] = !shown[size_t(row)];
  applyVisibility();
  say(content.rows[size_t(row)].name + (shown[size_t(row)] ? " shown" : " hidden"));
}

void SceneView::Impl::toggleLevelSlice() {
  if (slice.enabled && slice.level) {  // again: hide
    slice.enabled = false;
    slice_actor.setVisible(false);
    applyCut();
    return;
  }
  slice.level = true;
  slice.value_m = 1.0f;  // a floor plan at table height: walls, doors and furniture legs
  showSlice();
}

void SceneView::Impl::setSliceAxis(int axis) {
  if (slice.enabled && !slice.level && slice.axis == axis) {  // same key again: hide
    slice.enabled = false;
    slice_actor.setVisible(false);
    return;
  }
  slice.level = false;
  if (!slice_placed || slice.axis != axis) {  // a new axis starts in the middle of the scene
    const SliceRange r = sliceRange(content.scene, content.summary, axis);
    slice_index = (r.first + r.last) / 2;
  }
  slice.axis = axis;
  showSlice();
}

void SceneView::Impl::moveSlice(int voxels) {
  if (slice.level)
    slice.value_m += float(voxels) * content.scene.meta.voxel_size_m;
  else
    slice_index += voxels;
  showSlice();
}

void SceneView::Impl::exportVisible() {
  std::vector<TriangleMesh> colored;  // the colors on screen
  std::vector<const TriangleMesh*> meshes;
  for (size_t i = 0; i < content.parts.size(); ++i) {
    if (!content.rows.empty() && !shown[i]) continue;
    const ClassPart& part = content.parts[i];
    if (color_by_class) {
      colored.push_back(part.mesh);
      colored.back().colors = part.class_colors;
    }
  }
  size_t k = 0;
  for (size_t i = 0; i < content.parts.size(); ++i) {
    if (!content.rows.empty() && !shown[i]) continue;
    meshes.push_back(color_by_class ? &colored[k++] : &content.parts[i].mesh);
  }
  TriangleMesh merged = mergeMeshes(meshes);
  // Z-up like every PLY vdbfuse writes (vdb/scene_frame.h), so it stands upright in Blender too.
  const Rigid3f to_file = exportRotation(content.scene.meta, SceneAxes::kZUp);
  transformMesh(merged, to_file);
  if (merged.triangles.empty()) {
    say("export: nothing visible to export");
    return;
  }
  const std::string path = besideScene(content.scene_path, "_visible.ply");
  try {
    MeshWriteOptions write;
    write.with_class_property = merged.hasClasses();
    write.classes = &content.scene.meta.classes;
    write.frame = MeshFrame{sceneAxesName(SceneAxes::kZUp), to_file};
    writeMesh(merged, path, write);
    say("exported " + withThousands(merged.triangleCount()) + " triangles to " + path + " (Z-up)");
  } catch (const Error& e) {
    say(std::string("export failed: ") + e.what());
  }
}

void SceneView::Impl::screenshotKey() {
  std::string path;
  for (int i = 1; i < 1000; ++i) {
    char suffix[32];
    std::snprintf(suffix, sizeof suffix, "_view_%03d.png", i);
    path = besideScene(content.scene_path, suffix);
    if (!std::filesystem::exists(path)) break;
  }
  try {
    const bool help = help_text->GetVisibility();
    help_text->VisibilityOff();  // the picture is of the scene, not of the help
    const ColorImage image = capture();
    help_text->SetVisibility(help);
    writeColorPng(path, image);
    say("saved " + path);
  } catch (const Error& e) {
    say(std::string("screenshot failed: ") + e.what());
  }
}

void SceneView::Impl::onKey(char key, const std::string& keysym) {
  if (key >= '1' && key <= '9') {
    if (content.rows.empty()) say("no classes: the scene was fused without labels");
    toggleRow(key - '1');
  } else if (key == '0') {
    shown.assign(shown.size(), true);
    applyVisibility();
  } else if (key == 'h') {
    help_text->SetVisibility(!help_text->GetVisibility());
  } else if (key == 'c') {
    if (content.rows.empty()) {
      say("class coloring: the scene has no class grid (fused without labels), showing RGB");
    } else {
      color_by_class = !color_by_class;
      applyColors();
    }
  } else if (key == 'f' || key == 'r') {
    setCamera({CameraPreset::kFront, 0});
  } else if (key == 't') {
    setCamera({CameraPreset::kTop, 0});
  } else if (key == 'v') {
    setCamera({CameraPreset::kSide, 0});
  } else if (key == 'n') {
    if (content.trajectory.empty()) {
      say("no trajectory loaded (--trajectory FILE)");
    } else {
      // The next pose with a frustum after the current camera's, wrapping to the first.
      auto next = camera_frame < 0 ? frustum_poses.begin()
                                   : std::upper_bound(frustum_poses.begin(), frustum_poses.end(), size_t(camera_frame));
      setCamera({CameraPreset::kTrajectory, int(next == frustum_poses.end() ? frustum_poses.front() : *next)});
    }
  } else if (key == 'p' || key == 'k') {
    if (!trajectory_actor) {
      say("no trajectory loaded (--trajectory FILE)");
    } else {
      bool& flag = key == 'p' ? trajectory_shown : frusta_shown;
      flag = !flag;
      applyTrajectoryVisibility();
    }
  } else if (key == 'm') {
    surface_shown = !surface_shown;
    applyVisibility();
  } else if (key == 'b') {
    backfaces_shown = !backfaces_shown;
    applyVisibility();
  } else if (key == 'l') {
    toggleLevelSlice();
  } else if (key == 'x' || key == 'y' || key == 'z') {
    setSliceAxis(key - 'x');
  } else if (key == '[' || key == ']' || key == '{' || key == '}') {
    if (!slice.level && !slice_placed) {
      const SliceRange r = sliceRange(content.scene, content.summary, slice.axis);
      slice_index = (r.first + r.last) / 2;
    }
    moveSlice(key == '[' ? -1 : key == ']' ? 1 : key == '{' ? -10 : 10);
  } else if (key == 'g') {
    slice.grid = slice.grid == SliceGrid::kTsdf ? SliceGrid::kWeight : SliceGrid::kTsdf;
    showSlice();
  } else if (key == 's') {
    screenshotKey();
  } else if (key == 'e') {
    exportVisible();
  } else if (key == 'q' || keysym == "Escape") {
    if (interactor) interactor->TerminateApp();
    return;
  } else {
    return;  // not ours: no re-render
  }
  updateInfo();
  render();
}

bool SceneView::Impl::onClick(int x, int y) {
  const int row = panel.rowAt(x, y);
  if (row < 0) return false;
  toggleRow(row);
  updateInfo();
  render();
  return true;
}

SceneView::SceneView(SceneContent& content, const ViewOptions& options, bool offscreen)
    : impl_(std::make_unique<Impl>(content, options, offscreen)) {
  impl_->build();
}

SceneView::~SceneView() = default;

void SceneView::saveScreenshot(const std::string& path) {
  const PictureFormat format = pictureFormatFromPath(path);
  const ColorImage image = impl_->capture();
  if (format == PictureFormat::kJpeg)
    writeColorJpeg(path, image);
  else
    writeColorPng(path, image);
}

void SceneView::run() {
  vtkNew<vtkRenderWindowInteractor> interactor;
  vtkNew<ViewInteractorStyle> style;
  Impl* impl = impl_.get();
  style->on_key = [impl](char key, const std::string& keysym) { impl->onKey(key, keysym); };
  style->on_click = [impl](int x, int y) { return impl->onClick(x, y); };
  interactor->SetRenderWindow(impl->window);
  interactor->SetInteractorStyle(style);
  impl->interactor = interactor;
  interactor->Initialize();
  impl->render();
  interactor->Start();
  impl->interactor = nullptr;
}

std::string SceneView::cameraReport() const {
  vtkCamera* cam = impl_->renderer->GetActiveCamera();
  double dir[3], up[3];
  cam->GetDirectionOfProjection(dir);
  cam->OrthogonalizeViewUp();
  cam->GetViewUp(up);
  const LevelFrame& f = impl_->content.frame;
  const double scene_up[3] = {f.up.x, f.up.y, f.up.z};
  char buf[160];
  std::snprintf(buf, sizeof buf, "; floor at %.3f m along up", f.floor_m);
  std::string text = "camera direction " + vectorText(dir) + ", view-up " + vectorText(up) + "; scene up " +
                     vectorText(scene_up) + " (" + (f.up_source.empty() ? "?" : f.up_source) + ")" + buf;
  if (impl_->slice.enabled) {
    const Vec3f n = impl_->slice_image.normal;
    const double normal[3] = {n.x, n.y, n.z};
    text += "\nslice normal " + vectorText(normal);
  }
  return text;
}

double SceneView::buildSeconds() const { return impl_->build_s; }
double SceneView::firstRenderSeconds() const { return impl_->first_render_s; }
const std::vector<std::string>& SceneView::notices() const { return impl_->notices; }

}  // namespace vf::viewer
