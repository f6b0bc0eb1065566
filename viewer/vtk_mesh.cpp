#include "viewer/vtk_mesh.h"

#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnsignedCharArray.h>

#include <cstring>

namespace vf::viewer {
namespace {

vtkSmartPointer<vtkUnsignedCharArray> colorArray(const char* name, const std::vector<Rgb8>& colors, size_t n) {
  auto a = vtkSmartPointer<vtkUnsignedCharArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(3);
  a->SetNumberOfTuples(vtkIdType(n));
  unsigned char* out = a->GetPointer(0);
  for (size_t i = 0; i < n; ++i) {
    const Rgb8 c = colors.empty() ? Rgb8{255, 255, 255, 255} : colors[i];
    out[3 * i] = c.r, out[3 * i + 1] = c.g, out[3 * i + 2] = c.b;
  }
  return a;
}

}  // namespace

vtkSmartPointer<vtkPolyData> toPolyData(const TriangleMesh& mesh, const std::vector<Rgb8>& class_colors) {
  const size_t n = mesh.vertexCount();
  static_assert(sizeof(Vec3f) == 3 * sizeof(float), "Vec3f must be three packed floats");
  auto coords = vtkSmartPointer<vtkFloatArray>::New();
  coords->SetNumberOfComponents(3);
  coords->SetNumberOfTuples(vtkIdType(n));
  if (n) std::memcpy(coords->GetPointer(0), mesh.positions.data(), n * sizeof(Vec3f));
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetData(coords);

  // Triangles as offsets + connectivity (VTK 9 layout): two flat arrays, no per-cell insert.
  auto offsets = vtkSmartPointer<vtkIdTypeArray>::New();
  auto connectivity = vtkSmartPointer<vtkIdTypeArray>::New();
  const size_t t = mesh.triangleCount();
  offsets->SetNumberOfTuples(vtkIdType(t + 1));
  connectivity->SetNumberOfTuples(vtkIdType(3 * t));
  vtkIdType* off = offsets->GetPointer(0);
  vtkIdType* con = connectivity->GetPointer(0);
  for (size_t f = 0; f < t; ++f) {
    off[f] = vtkIdType(3 * f);
    for (int k = 0; k < 3; ++k) con[3 * f + k] = mesh.triangles[f][k];
  }
  off[t] = vtkIdType(3 * t);
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  cells->SetData(offsets, connectivity);

  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetPolys(cells);
  if (mesh.hasNormals()) {
    auto normals = vtkSmartPointer<vtkFloatArray>::New();
    normals->SetName("Normals");
    normals->SetNumberOfComponents(3);
    normals->SetNumberOfTuples(vtkIdType(n));
    std::memcpy(normals->GetPointer(0), mesh.normals.data(), n * sizeof(Vec3f));
    poly->GetPointData()->SetNormals(normals);
  }
  poly->GetPointData()->AddArray(colorArray(kRgbArray, mesh.colors, n));
  poly->GetPointData()->AddArray(colorArray(kClassArray, class_colors.empty() ? mesh.colors : class_colors, n));
  return poly;
}

}  // namespace vf::viewer
