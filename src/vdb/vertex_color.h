#pragma once
// The one rule for the colour of a surface vertex or point, shared by the mesher, the point
// cloud and the viewer: the class table's colour when class colours were asked for, else the
// fused colour (the color grid is linear; meshes carry sRGB bytes, core/color.h).
#include "core/class_table.h"
#include "core/color.h"

namespace vf {

enum class MeshColorMode { kRgb, kClass };

inline constexpr Rgb8 kUnlistedClassColor{128, 128, 128, 255};  // an id the class table lacks
inline constexpr Rgb8 kUncoloredSurface{200, 200, 200, 255};    // a scene without a color grid

inline Rgb8 classColorOf(const ClassTable& classes, int class_id) {
  const ClassInfo* info = classes.findId(class_id);
  return info ? info->color : kUnlistedClassColor;
}

// `linear_rgb` null: the scene has no color grid.
inline Rgb8 surfaceColor(MeshColorMode mode, const ClassTable& classes, int class_id, const Vec3f* linear_rgb) {
  if (mode == MeshColorMode::kClass) return classColorOf(classes, class_id);
  return linear_rgb ? linearToSrgb8(*linear_rgb) : kUncoloredSurface;
}

}  // namespace vf
