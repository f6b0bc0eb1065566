#include "core/camera_check.h"

#include <cstdio>

namespace vf {
namespace {

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

}  // namespace

std::string cameraProblem(const Intrinsics& k) {
  const float w = float(k.width), h = float(k.height);
  if (!(k.fx >= 0.005f * w && k.fx <= 60.f * w))
    return "fx = " + number(k.fx) + " is out of range for a " + std::to_string(k.width) +
           "-pixel-wide image (0.005 to 60 times the width)";
  if (!(k.fy >= 0.005f * h && k.fy <= 60.f * h))
    return "fy = " + number(k.fy) + " is out of range for a " + std::to_string(k.height) +
           "-pixel-high image (0.005 to 60 times the height)";
  if (!(k.cx >= 0.f && k.cx <= w))
    return "cx = " + number(k.cx) + " lies outside the " + std::to_string(k.width) +
           "-pixel-wide image (the principal point must lie inside it)";
  if (!(k.cy >= 0.f && k.cy <= h))
    return "cy = " + number(k.cy) + " lies outside the " + std::to_string(k.height) +
           "-pixel-high image (the principal point must lie inside it)";
  return "";
}

}  // namespace vf
