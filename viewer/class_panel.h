#pragma once
// The class panel overlay (top left): per class a color swatch, key number, name and voxel
// count; hidden classes dimmed with a hollow swatch; "no classes" for scenes fused without
// labels. VTK header: viewer/*.cpp only.
#include <vtkActor2D.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTextActor.h>

#include <vector>

#include "viewer/scene_content.h"

namespace vf::viewer {

class ClassPanel {
 public:
  void build(vtkRenderer* renderer, const std::vector<ClassRow>& rows, int font_px);
  void setShown(const std::vector<bool>& shown);  // per row
  // Positions everything for the renderer's current size (called before each render).
  void layout(vtkRenderer* renderer);
  // The row under display position (x, y) (origin bottom left), or -1.
  int rowAt(int x, int y) const;

 private:
  struct Row {
    vtkSmartPointer<vtkTextActor> name, count;
  };
  void rebuildGeometry();

  std::vector<ClassRow> rows_;
  std::vector<bool> shown_;
  std::vector<Row> texts_;
  vtkSmartPointer<vtkTextActor> title_;
  vtkNew<vtkPolyData> shapes_;  // background + swatches, display coordinates
  vtkNew<vtkActor2D> shapes_actor_;
  int font_px_ = 16;
  // Layout results (display pixels).
  int left_ = 0, top_ = 0, width_ = 0, row_h_ = 0, first_row_top_ = 0;
};

// "2,528,527"
std::string withThousands(size_t n);

}  // namespace vf::viewer
