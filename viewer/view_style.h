#pragma once
// Colors and constants of the picture that the tests need too (plain header, no VTK).
namespace vf::viewer {

// Neutral gradient background, darker at the bottom: a lit surface of any color stands out.
inline constexpr double kBackgroundBottom[3] = {0.20, 0.21, 0.23};
inline constexpr double kBackgroundTop[3] = {0.55, 0.57, 0.60};

// Slice color maps' end colors: tsdf by Moreland's cool-warm (blue inside / behind the surface,
// red in front of it), weight by viridis (dark violet: few observations, yellow: many).
inline constexpr double kTsdfLowRgb[3] = {0.230, 0.299, 0.754}, kTsdfHighRgb[3] = {0.706, 0.016, 0.150};
inline constexpr double kWeightLowRgb[3] = {0.267, 0.005, 0.329}, kWeightHighRgb[3] = {0.993, 0.906, 0.144};

// Trajectory line and frustum color.
inline constexpr unsigned char kTrajectoryColor[3] = {255, 170, 30};

// Vertical field of view of the frustums and of the trajectory camera when the scene does not
// record its camera (files written before it did): a Kinect/Xtion (TUM), 2 atan(240 / 525).
inline constexpr double kTrajectoryFovYDeg = 49.1;

// Class colours darker than this (Rec. 709 luma of the sRGB bytes) are lightened to it, keeping
// their hue: the palette gives id 0 ("background") black, which vanished into the dark
// backdrop (kBackgroundBottom is luma 53).
inline constexpr double kMinClassLuma = 110;

}  // namespace vf::viewer
