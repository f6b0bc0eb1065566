#pragma once
// A SliceImage shown in the scene (unobserved voxels transparent) with its color bar on the
// right, titled with the grid's name and units. VTK header: viewer/*.cpp only.
#include <vtkImageActor.h>
#include <vtkImageData.h>
#include <vtkImageMapToColors.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>

#include "viewer/slice.h"
#include "viewer/view_style.h"

namespace vf::viewer {

class SliceActor {
 public:
  void attach(vtkRenderer* renderer, int font_px);
  void show(const SliceImage& slice);
  void setVisible(bool visible);

 private:
  void buildLookupTable(const SliceImage& slice);

  vtkNew<vtkImageData> image_;
  vtkNew<vtkLookupTable> lut_;
  vtkNew<vtkImageMapToColors> colors_;
  vtkNew<vtkImageActor> actor_;
  vtkNew<vtkScalarBarActor> bar_;
};

}  // namespace vf::viewer
