#include "viewer/class_panel.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkPoints.h>
#include <vtkPolyDataMapper2D.h>
#include <vtkProperty2D.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>

namespace vf::viewer {
namespace {

vtkSmartPointer<vtkTextActor> makeText(vtkRenderer* renderer, int font_px) {
  auto t = vtkSmartPointer<vtkTextActor>::New();
  vtkTextProperty* p = t->GetTextProperty();
  p->SetFontSize(font_px);
  p->SetColor(1, 1, 1);
  p->ShadowOn();
  p->SetVerticalJustificationToCentered();
  t->PickableOff();
  renderer->AddActor2D(t);
  return t;
}

double textWidth(vtkTextActor* t, vtkRenderer* renderer) {
  double box[4] = {0, 0, 0, 0};
  t->GetBoundingBox(renderer, box);
  return box[1] - box[0];
}

}  // namespace

std::string withThousands(size_t n) {
  std::string digits = std::to_string(n), out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

void ClassPanel::build(vtkRenderer* renderer, const std::vector<ClassRow>& rows, int font_px) {
  rows_ = rows;
  shown_.assign(rows.size(), true);
  font_px_ = font_px;
  // 2D actors draw in the order they were added: the translucent background and swatches first,
  // the texts over them.
  vtkNew<vtkPolyDataMapper2D> mapper;
  mapper->SetInputData(shapes_);
  mapper->SetScalarModeToUseCellData();
  mapper->SetColorModeToDirectScalars();
  shapes_actor_->SetMapper(mapper);
  shapes_actor_->PickableOff();
  renderer->AddActor2D(shapes_actor_);
  title_ = makeText(renderer, font_px);
  title_->GetTextProperty()->BoldOn();
  title_->SetInput(rows.empty() ? "no classes (fused without labels)" : "classes  (1-9 or click: show/hide, 0: all)");
  for (size_t i = 0; i < rows.size(); ++i) {
    Row r{makeText(renderer, font_px), makeText(renderer, font_px)};
    const std::string key = i < 9 ? std::to_string(i + 1) + "  " : "    ";
    r.name->SetInput((key + rows[i].name).c_str());
    r.count->SetInput((withThousands(rows[i].voxels) + " voxels").c_str());
    r.count->GetTextProperty()->SetJustificationToRight();
    texts_.push_back(r);
  }
}

void ClassPanel::setShown(const std::vector<bool>& shown) {
  shown_ = shown;
  for (size_t i = 0; i < texts_.size(); ++i) {
    const double gray = shown_[i] ? 1.0 : 0.55;
    for (vtkTextActor* t : {texts_[i].name.Get(), texts_[i].count.Get()}) {
      t->GetTextProperty()->SetColor(gray, gray, gray);
      t->GetTextProperty()->SetItalic(!shown_[i]);
    }
  }
  rebuildGeometry();
}

void ClassPanel::layout(vtkRenderer* renderer) {
  const int* size = renderer->GetSize();
  const int margin = font_px_;
  row_h_ = int(font_px_ * 1.6);
  left_ = margin;
  top_ = size[1] - margin;
  // Width: the widest name and count plus the swatch and gaps.
  double name_w = textWidth(title_, renderer), count_w = 0;
  double rows_name_w = 0;
  for (const Row& r : texts_) {
    rows_name_w = std::max(rows_name_w, textWidth(r.name, renderer));
    count_w = std::max(count_w, textWidth(r.count, renderer));
  }
  const int pad = font_px_ / 2, swatch = font_px_;
  const int rows_w = int(swatch + pad + rows_name_w + 2 * font_px_ + count_w);
  width_ = 2 * pad + std::max(int(name_w), rows_w);
  const int title_y = top_ - pad - row_h_ / 2;
  title_->SetPosition(left_ + pad, title_y);
  first_row_top_ = top_ - pad - row_h_;
  for (size_t i = 0; i < texts_.size(); ++i) {
    const int y = first_row_top_ - int(i) * row_h_ - row_h_ / 2;
    texts_[i].name->SetPosition(left_ + pad + swatch + pad, y);
    texts_[i].count->SetPosition(left_ + width_ - pad, y);
  }
  rebuildGeometry();
}

void ClassPanel::rebuildGeometry() {
  if (row_h_ == 0) return;  // not laid out yet
  auto points = vtkSmartPointer<vtkPoints>::New();
  auto polys = vtkSmartPointer<vtkCellArray>::New();
  auto colors = vtkSmartPointer<vtkUnsignedCharArray>::New();
  colors->SetNumberOfComponents(4);
  auto quad = [&](double x0, double y0, double x1, double y1, const unsigned char rgba[4]) {
    const vtkIdType base = points->GetNumberOfPoints();
    points->InsertNextPoint(x0, y0, 0);
    points->InsertNextPoint(x1, y0, 0);
    points->InsertNextPoint(x1, y1, 0);
    points->InsertNextPoint(x0, y1, 0);
    const vtkIdType ids[4] = {base, base + 1, base + 2, base + 3};
    polys->InsertNextCell(4, ids);
    colors->InsertNextTypedTuple(rgba);
  };
  const int pad = font_px_ / 2, swatch = font_px_;
  const int bottom = first_row_top_ - int(rows_.size()) * row_h_ - pad;
  const unsigned char panel_bg[4] = {20, 22, 26, 150};
  quad(left_, bottom, left_ + width_, top_, panel_bg);
  for (size_t i = 0; i < rows_.size(); ++i) {
    const double cy = first_row_top_ - double(i) * row_h_ - row_h_ / 2.0;
    const double x0 = left_ + pad, y0 = cy - swatch / 2.0;
    const Rgb8 c = rows_[i].color;
    const unsigned char border[4] = {235, 235, 235, 255};
    quad(x0 - 1, y0 - 1, x0 + swatch + 1, y0 + swatch + 1, border);
    // Hidden: a hollow swatch (the class color shows only as a thin ring).
    const unsigned char fill[4] = {c.r, c.g, c.b, 255};
    const unsigned char hollow[4] = {panel_bg[0], panel_bg[1], panel_bg[2], 255};
    quad(x0, y0, x0 + swatch, y0 + swatch, fill);
    if (!shown_[i]) quad(x0 + 3, y0 + 3, x0 + swatch - 3, y0 + swatch - 3, hollow);
  }
  shapes_->SetPoints(points);
  shapes_->SetPolys(polys);
  shapes_->GetCellData()->SetScalars(colors);
  shapes_->Modified();
}

int ClassPanel::rowAt(int x, int y) const {
  if (x < left_ || x > left_ + width_) return -1;
  const int offset = first_row_top_ - y;
  if (offset < 0) return -1;
  const int row = offset / std::max(1, row_h_);
  return row < int(rows_.size()) ? row : -1;
}

}  // namespace vf::viewer
