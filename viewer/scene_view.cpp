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
    "f  t  v  camera: front (as the first frame) / top / side\n"
    "n        camera: next trajectory frustum\n"
    "p        trajectory on / off\n"
    "x y z    slice across x / y / z  (same key again: hide)\n"
    "[  ]     move the slice one voxel   ({  }: ten voxels)\n"
    "g        slice grid: tsdf  <->  weight\n"
    "s        save a screenshot PNG next to the scene\n"
    "e        export the visible classes to <scene>_visible.ply\n"
    "q  Esc   quit";

// Places the camera looking along `dir` (with `up` up) at the box's centre, just far enough that
// every corner of the box is inside the view: tighter than VTK's ResetCamera, which fits the
// bounding sphere and leaves a flat scene small in the middle.
void fitView(vtkCamera* cam, const double dir[3], const double up[3], const double bounds[6], double fov_y_deg,
             double aspect) {
  const double c[3] = {0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), 0.5 * (bounds[4] + bounds[5])};
  const double right[3] = {dir[1] * up[2] - dir[2] * up[1], dir[2] * up[0] - dir[0] * up[2],
                           dir[0] * up[1] - dir[1] * up[0]};
  const double tan_y = std::tan(0.5 * fov_y_deg * M_PI / 180.0), tan_x = tan_y * aspect;
  double distance = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const double p[3] = {bounds[corner & 1] - c[0], bounds[2 + ((corner >> 1) & 1)] - c[1],
                         bounds[4 + ((corner >> 2) & 1)] - c[2]};
    const double x = p[0] * right[0] + p[1] * right[1] + p[2] * right[2];
    const double y = p[0] * up[0] + p[1] * up[1] + p[2] * up[2];
    const double z = p[0] * dir[0] + p[1] * dir[1] + p[2] * dir[2];
    // The corner at depth (distance + z) in front of the eye must satisfy |x| <= depth tan_x.
    distance = std::max(distance, std::max(std::abs(x) / tan_x, std::abs(y) / tan_y) - z);
  }
  distance = std::max(distance * 1.05, 1e-3);  // a small margin around the surface
  cam->SetFocalPoint(c[0], c[1], c[2]);
  cam->SetPosition(c[0] - distance * dir[0], c[1] - distance * dir[1], c[2] - distance * dir[2]);
  cam->SetViewUp(up[0], up[1], up[2]);
  cam->SetViewAngle(fov_y_deg);
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
  vtkSmartPointer<vtkActor> trajectory_actor;
  bool trajectory_shown = false;
  std::vector<size_t> frustum_poses;  // poses with a frustum: what 'n' steps through
  int camera_frame = -1;
  SliceActor slice_actor;
  SliceSpec slice;
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
    slice_index = sliceIndexAt(content.scene, content.summary, slice.axis, slice.value_m);
    showSlice();
  }
  applyColors();
  applyVisibility();
  CameraSpec camera = options.camera;
  if (!options.camera_given && slice.enabled) camera.preset = cameraFacingAxis(slice.axis);
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
    renderer->AddActor(actor);
    part_mappers.push_back(mapper);
    part_actors.push_back(actor);
  }
  shown.assign(content.rows.size(), true);
}

void SceneView::Impl::buildTrajectory() {
  if (content.trajectory.empty()) return;
  const Vec3f d = content.surface_max_m - content.surface_min_m;
  const double depth_m = std::max(0.02, 0.035 * double(norm(d)));  // small next to the scene
  frustum_poses = frustumPoses(content.trajectory, options.frustum_every, 1.5 * depth_m);
  trajectory_actor =
      makeTrajectoryActor(content.trajectory, frustum_poses, depth_m, frameCamera(content.scene.meta.depth_intrinsics));
  renderer->AddActor(trajectory_actor);
  trajectory_shown = options.show_trajectory;
  trajectory_actor->SetVisibility(trajectory_shown);
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
  if (!content.rows.empty())
    for (size_t i = 0; i < part_actors.size(); ++i) part_actors[i]->SetVisibility(shown[i]);
  panel.setShown(shown);
}

void SceneView::Impl::setCamera(const CameraSpec& spec) {
  vtkCamera* cam = renderer->GetActiveCamera();
  const Vec3f lo = content.surface_min_m, hi = content.surface_max_m;
  double bounds[6] = {lo.x, hi.x, lo.y, hi.y, lo.z, hi.z};
  if (trajectory_actor && trajectory_shown) {  // the cameras belong in the picture too
    for (const StampedPose& p : content.trajectory)
      for (int a = 0; a < 3; ++a) {
        bounds[2 * a] = std::min(bounds[2 * a], p.T_world_cam.translation()[a]);
        bounds[2 * a + 1] = std::max(bounds[2 * a + 1], p.T_world_cam.translation()[a]);
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
    const FrameCamera frame = frameCamera(content.scene.meta.depth_intrinsics);
    const int* size = window->GetSize();
    const double window_aspect = size[1] > 0 ? double(size[0]) / size[1] : 1.0;
    const double tan_y = std::tan(0.5 * frame.fov_y_deg * M_PI / 180.0);
    cam->SetUseHorizontalViewAngle(window_aspect < frame.aspect);
    cam->SetViewAngle(window_aspect < frame.aspect ? 2.0 * std::atan(tan_y * frame.aspect) * 180.0 / M_PI
                                                   : frame.fov_y_deg);
    camera_frame = spec.frame;
    // Seen from a recorded camera the frustums would frame the picture itself: hide the path
    // until the camera leaves the trajectory.
    if (trajectory_actor) trajectory_actor->SetVisibility(false);
  } else {
    // Axis views (view_options.h): the direction of projection and the picture's up.
    const double dirs[3][3] = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}};  // front, top, side
    const double ups[3][3] = {{0, -1, 0}, {0, 0, 1}, {0, -1, 0}};
    const int k = spec.preset == CameraPreset::kFront ? 0 : spec.preset == CameraPreset::kTop ? 1 : 2;
    const int* size = window->GetSize();
    const double aspect = size[1] > 0 ? double(size[0]) / size[1] : 1.0;
    cam->SetUseHorizontalViewAngle(false);
    fitView(cam, dirs[k], ups[k], bounds, 30.0, aspect);
    camera_frame = -1;
    if (trajectory_actor) trajectory_actor->SetVisibility(trajectory_shown);
  }
  renderer->ResetCameraClippingRange();
}

void SceneView::Impl::showSlice() {
  const SliceImage image = sampleSlice(content.scene, content.summary, slice.grid, slice.axis, slice_index);
  slice_index = image.index;
  slice.value_m = image.value_m;
  slice.enabled = true;
  slice_placed = true;
  slice_actor.show(image);
}

void SceneView::Impl::updateInfo() {
  char buf[512];
  std::snprintf(buf, sizeof buf, "%s    %s triangles    color: %s",
                std::filesystem::path(content.scene_path).filename().string().c_str(),
                withThousands(content.triangles).c_str(), color_by_class ? "class" : "rgb");
  std::string info = buf;
  if (slice.enabled) {
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

void SceneView::Impl::setSliceAxis(int axis) {
  if (slice.enabled && slice.axis == axis) {  // same key again: hide
    slice.enabled = false;
    slice_actor.setVisible(false);
    return;
  }
  if (!slice_placed || slice.axis != axis) {  // a new axis starts in the middle of the scene
    const SliceRange r = sliceRange(content.scene, content.summary, axis);
    slice_index = (r.first + r.last) / 2;
  }
  slice.axis = axis;
  showSlice();
}

void SceneView::Impl::moveSlice(int voxels) {
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
  } else if (key == 'p') {
    if (!trajectory_actor) {
      say("no trajectory loaded (--trajectory FILE)");
    } else {
      trajectory_shown = !trajectory_shown;
      trajectory_actor->SetVisibility(trajectory_shown && camera_frame < 0);
    }
  } else if (key == 'x' || key == 'y' || key == 'z') {
    setSliceAxis(key - 'x');
  } else if (key == '[' || key == ']' || key == '{' || key == '}') {
    if (!slice_placed) {
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

double SceneView::buildSeconds() const { return impl_->build_s; }
double SceneView::firstRenderSeconds() const { return impl_->first_render_s; }
const std::vector<std::string>& SceneView::notices() const { return impl_->notices; }

}  // namespace vf::viewer
