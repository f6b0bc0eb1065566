#include "viewer/slice_actor.h"

#include <vtkColorTransferFunction.h>
#include <vtkFloatArray.h>
#include <vtkImageMapper3D.h>
#include <vtkImageProperty.h>
#include <vtkMatrix4x4.h>
#include <vtkPointData.h>
#include <vtkTextProperty.h>


namespace vf::viewer {

void SliceActor::attach(vtkRenderer* renderer, int font_px) {
  colors_->SetInputData(image_);
  colors_->SetLookupTable(lut_);
  colors_->SetOutputFormatToRGBA();
  actor_->GetMapper()->SetInputConnection(colors_->GetOutputPort());
  actor_->InterpolateOff();  // one flat square per voxel: what was sampled, not a blur of it
  actor_->PickableOff();
  actor_->VisibilityOff();
  renderer->AddActor(actor_);

  bar_->SetLookupTable(lut_);
  bar_->SetOrientationToVertical();
  bar_->SetNumberOfLabels(5);
  bar_->SetUnconstrainedFontSize(true);  // fixed pixel sizes: readable at any window size
  bar_->SetPosition(0.89, 0.15);
  bar_->SetWidth(0.10);
  bar_->SetHeight(0.66);
  bar_->SetBarRatio(0.3);
  bar_->SetTextPositionToSucceedScalarBar();
  bar_->SetVerticalTitleSeparation(font_px / 2);  // keep the title off the top label
  for (vtkTextProperty* t : {bar_->GetTitleTextProperty(), bar_->GetLabelTextProperty()}) {
    t->SetColor(1, 1, 1);
    t->ShadowOn();
    t->BoldOff();
    t->ItalicOff();
    t->SetFontSize(font_px);
  }
  bar_->GetTitleTextProperty()->BoldOn();
  bar_->VisibilityOff();
  renderer->AddActor2D(bar_);
}

void SliceActor::buildLookupTable(const SliceImage& slice) {
  vtkNew<vtkColorTransferFunction> ctf;
  const double scale = sliceDisplayScale(slice.grid), lo = slice.range_min * scale, hi = slice.range_max * scale;
  if (slice.grid == SliceGrid::kTsdf) {
    ctf->SetColorSpaceToDiverging();
    ctf->AddRGBPoint(lo, kTsdfLowRgb[0], kTsdfLowRgb[1], kTsdfLowRgb[2]);
    ctf->AddRGBPoint(hi, kTsdfHighRgb[0], kTsdfHighRgb[1], kTsdfHighRgb[2]);
    bar_->SetLabelFormat("%+.0f");
  } else {
    // viridis at five stops
    const double stops[5][3] = {{0.267, 0.005, 0.329}, {0.230, 0.322, 0.546}, {0.128, 0.567, 0.551},
                                {0.369, 0.789, 0.383}, {0.993, 0.906, 0.144}};
    for (int i = 0; i < 5; ++i)
      ctf->AddRGBPoint(lo + (hi - lo) * i / 4.0, stops[i][0], stops[i][1], stops[i][2]);
    bar_->SetLabelFormat("%.0f");
  }
  const int n = 256;
  lut_->SetNumberOfTableValues(n);
  lut_->SetRange(lo, hi);
  for (int i = 0; i < n; ++i) {
    double rgb[3];
    ctf->GetColor(lo + (hi - lo) * i / (n - 1.0), rgb);
    lut_->SetTableValue(i, rgb[0], rgb[1], rgb[2], 1.0);
  }
  lut_->SetNanColor(0, 0, 0, 0);  // unobserved voxels: see-through
  lut_->Modified();
  bar_->SetTitle(sliceTitle(slice.grid).c_str());
}

void SliceActor::show(const SliceImage& slice) {
  // The image lies in its own x-y plane from (0, 0, 0); the actor's matrix turns it onto the
  // slice's plane: columns u, v, normal and the origin (axis slices and floor plans alike).
  image_->SetDimensions(slice.width, slice.height, 1);
  image_->SetOrigin(0, 0, 0);
  image_->SetSpacing(slice.spacing_m, slice.spacing_m, slice.spacing_m);
  vtkNew<vtkMatrix4x4> place;
  const Vec3f columns[4] = {slice.u_dir, slice.v_dir, slice.normal, slice.origin_m};
  for (int c = 0; c < 4; ++c) {
    place->SetElement(0, c, columns[c].x);
    place->SetElement(1, c, columns[c].y);
    place->SetElement(2, c, columns[c].z);
  }
  actor_->SetUserMatrix(place);
  vtkNew<vtkFloatArray> values;
  values->SetNumberOfTuples(vtkIdType(slice.values.size()));
  const float scale = sliceDisplayScale(slice.grid);
  for (size_t i = 0; i < slice.values.size(); ++i) values->SetValue(vtkIdType(i), slice.values[i] * scale);
  image_->GetPointData()->SetScalars(values);
  image_->Modified();
  buildLookupTable(slice);
  colors_->Update();
  int extent[6];
  image_->GetExtent(extent);
  actor_->SetDisplayExtent(extent);
  setVisible(true);
}

void SliceActor::setVisible(bool visible) {
  actor_->SetVisibility(visible);
  bar_->SetVisibility(visible);
}

}  // namespace vf::viewer
