#pragma once
// TriangleMesh -> vtkPolyData. VTK header: included only by viewer/*.cpp.
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <vector>

#include "core/mesh.h"

namespace vf::viewer {

// Point arrays: "Normals" (when the mesh has them), "rgb" (mesh.colors, or white) and "class"
// (class_colors; "rgb" again when that is empty), both unsigned char x3, so the coloring is
// switched by selecting an array, with no copy.
vtkSmartPointer<vtkPolyData> toPolyData(const TriangleMesh& mesh, const std::vector<Rgb8>& class_colors);

inline constexpr const char* kRgbArray = "rgb";
inline constexpr const char* kClassArray = "class";

}  // namespace vf::viewer
