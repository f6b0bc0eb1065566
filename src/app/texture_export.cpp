// Simplify, chart, bake, encode: the textured-mesh path of `mesh` and `export --blender`.
#include "app/texture_export.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <utility>

#include "app/progress.h"
#include "core/error.h"
#include "io/image_codec.h"
#include "texture/mesh_simplify.h"
#include "texture/texture_bake.h"
#include "texture/uv_atlas.h"

namespace vf::app {

void addSimplifyOptions(CLI::App& cmd, TextureCliOptions& o) {
  cmd.add_option("--target-triangles", o.target_triangles,
                 "simplify to at most this many triangles (edge collapses; walls become few large triangles)");
  cmd.add_option("--max-error-mm", o.max_error_mm,
                 "simplification never moves the surface further than this (it then keeps more triangles)")
      ->capture_default_str();
}

void addTextureOptions(CLI::App& cmd, TextureCliOptions& o) {
  cmd.add_flag("--texture", o.texture,
               "bake a colour texture from the input frames (UV atlas; GLB embeds it, OBJ writes it beside)");
  cmd.add_option("--texel-mm", o.texel_mm, "--texture: texel size on the surface (coarser when the page would exceed --texture-size)")
      ->capture_default_str();
  cmd.add_option("--texture-size", o.max_texture_px, "--texture: the largest texture page (a power of two, 256..8192)")
      ->capture_default_str();
  cmd.add_option("--texture-format", o.image_format, "--texture: image format")
      ->check(CLI::IsMember({"jpg", "png"}))
      ->capture_default_str();
  cmd.add_option("--frames", o.frames.frames, "--texture: the capture to bake from (default: the one the scene was fused from)");
  cmd.add_option("--trajectory", o.frames.trajectory,
                 "--texture: the poses the frames were fused at (TUM; default: the scene's own, else <scene>.txt)");
  cmd.add_option("--labels", o.frames.labels, "--texture: label maps for masking classes (default: the scene's)");
  cmd.add_option("--bake-max-frames", o.frames.max_frames, "--texture: use at most this many frames, evenly spaced")
      ->capture_default_str();
}

void checkTextureOptions(const TextureCliOptions& o) {
  if (o.target_triangles < 0) throw Error("--target-triangles " + std::to_string(o.target_triangles) + ": expected >= 0");
  if (!(o.max_error_mm >= 0)) throw Error("--max-error-mm must be >= 0");
  if (!(o.texel_mm > 0.05f && o.texel_mm < 1000.f)) throw Error("--texel-mm must be in (0.05, 1000)");
  // Overrides that name nothing fail before the meshing, not after it.
  for (const auto& [option, path] : {std::pair<const char*, std::string>{"--frames", o.frames.frames},
                                     {"--trajectory", o.frames.trajectory}, {"--labels", o.frames.labels}})
    if (!path.empty() && !std::filesystem::exists(path)) throw Error(std::string(option) + " " + path + ": no such file or folder");
  const int s = o.max_texture_px;
  if (s < 256 || s > 8192 || (s & (s - 1)) != 0)
    throw Error("--texture-size " + std::to_string(s) + ": expected a power of two from 256 to 8192");
}

void simplifyIfAsked(TriangleMesh& mesh, const TextureCliOptions& o) {
  if (o.target_triangles <= 0 || mesh.triangleCount() <= size_t(o.target_triangles)) return;
  const auto t0 = std::chrono::steady_clock::now();
  SimplifyOptions options;
  options.target_triangles = size_t(o.target_triangles);
  options.max_error_m = o.max_error_mm / 1000.f;
  SimplifyReport r;
  mesh = simplifyMesh(mesh, options, &r);
  std::printf("simplified %zu -> %zu triangles (largest deviation %.1f mm, %.2f s)%s\n", r.triangles_before,
              r.triangles_after, r.error_m * 1000.f, secondsSince(t0),
              r.triangles_after > size_t(o.target_triangles) ? "; --max-error-mm stopped it before the target" : "");
}

TexturedMesh bakeTexturedMesh(const Scene& scene, const std::string& scene_path, const TriangleMesh& mesh,
                              const std::set<int>& masked_classes, const TextureCliOptions& o) {
  auto t0 = std::chrono::steady_clock::now();
  const BakeFrames frames = loadBakeFrames(scene, scene_path, masked_classes, o.frames);
  std::printf("bake frames: %zu of %d from %s at the poses of %s (%d blurred left out%s) (%.2f s)\n", frames.views.size(),
              frames.frames_in_capture, frames.capture.c_str(), frames.poses_from.c_str(), frames.frames_blurred,
              frames.frames_unlabelled ? (", " + std::to_string(frames.frames_unlabelled) + " without label map").c_str() : "",
              secondsSince(t0));
  t0 = std::chrono::steady_clock::now();
  UvAtlasOptions atlas_options;
  atlas_options.texel_m = o.texel_mm / 1000.f;
  atlas_options.max_page_px = o.max_texture_px;
  const UvAtlas atlas = buildUvAtlas(mesh, atlas_options);
  std::printf("UV atlas: %zu charts on a %dx%d page, texels of %.2f mm (%.2f s)\n", atlas.charts.size(), atlas.page_px,
              atlas.page_px, atlas.texel_m * 1000.f, secondsSince(t0));
  t0 = std::chrono::steady_clock::now();
  BakeReport report;
  BakeOptions bake_options;
  // The bake is the long part of a textured export: a progress bar with its ETA on a terminal
  // (logs get the step's time below instead).
  ProgressBar progress(int(mesh.triangleCount()), isatty(STDERR_FILENO) != 0, "faces");
  bake_options.on_progress = [&](size_t done, size_t) { progress.update(int(done)); };
  const ColorImage page = bakeTexture(mesh, atlas, frames.views, bake_options, &report);
  progress.finish();
  std::printf("baked %zu texels: %.1f %% from frames, %.1f %% from the fused colour (%.2f s: views %.2f, texels %.2f, gutters %.2f)\n",
              report.texels, 100.0 * double(report.from_frames) / double(std::max<size_t>(report.texels, 1)),
              100.0 * double(report.from_fallback) / double(std::max<size_t>(report.texels, 1)), secondsSince(t0),
              report.select_s, report.bake_s, report.dilate_s);
  t0 = std::chrono::steady_clock::now();
  TexturedMesh out;
  out.page_px = atlas.page_px;
  out.mesh = applyAtlas(mesh, atlas);
  out.texture.extension = o.image_format;
  if (o.image_format == "png") {
    std::vector<uint8_t> rgb(size_t(page.width()) * size_t(page.height()) * 3);
    for (size_t i = 0; i < size_t(page.width()) * size_t(page.height()); ++i) {
      const Rgb8 c = page.data()[i];
      rgb[i * 3] = c.r, rgb[i * 3 + 1] = c.g, rgb[i * 3 + 2] = c.b;
    }
    out.texture.encoded = encodePng(rgb.data(), page.width(), page.height(), 3, 8, "texture");
  } else {
    out.texture.encoded = encodeJpeg(page, o.jpeg_quality, "texture");
  }
  std::printf("encoded the texture: %s, %.1f MB (%.2f s)\n", o.image_format.c_str(),
              double(out.texture.encoded.size()) / 1e6, secondsSince(t0));
  return out;
}

}  // namespace vf::app
