#include "qTissueMosaicViewLegends.h"

#include <vtkActor2D.h>
#include <vtkAxesActor.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCaptionActor2D.h>
#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkOrientationMarkerWidget.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper2D.h>
#include <vtkProperty2D.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include <cmath>
#include <cstdio>

namespace {

constexpr double kPi = 3.14159265358979323846;

/// The scale bar's length on screen aims at this many pixels (it lies between 0.4 and 1 times it).
constexpr double kTargetBarPx = 160;

/// The largest 1, 2 or 5 times a power of ten that is at most `limit`.
double roundLength(double limit) {
  const double power = std::pow(10.0, std::floor(std::log10(limit)));
  for (double step : {5.0, 2.0, 1.0}) {
    if (step * power <= limit) return step * power;
  }
  return power;
}

}  // namespace

qTissueMosaicViewLegends::qTissueMosaicViewLegends(vtkRenderer* renderer, vtkRenderWindowInteractor* interactor)
    : Renderer(renderer),
      Bar(vtkSmartPointer<vtkActor2D>::New()),
      BarPoints(vtkSmartPointer<vtkPoints>::New()),
      Label(vtkSmartPointer<vtkTextActor>::New()),
      Axes(vtkSmartPointer<vtkOrientationMarkerWidget>::New()),
      RenderCallback(vtkSmartPointer<vtkCallbackCommand>::New()) {
  // The bar: a line with end ticks, in display pixels (points set before every render).
  this->BarPoints->SetNumberOfPoints(6);
  vtkNew<vtkCellArray> lines;
  const vtkIdType segments[3][2] = {{0, 1}, {2, 3}, {4, 5}};
  for (const auto& segment : segments) lines->InsertNextCell(2, segment);
  vtkNew<vtkPolyData> bar;
  bar->SetPoints(this->BarPoints);
  bar->SetLines(lines);
  vtkNew<vtkPolyDataMapper2D> mapper;
  mapper->SetInputData(bar);
  this->Bar->SetMapper(mapper);
  this->Bar->GetProperty()->SetColor(1, 1, 1);
  this->Bar->GetProperty()->SetLineWidth(2);
  this->Bar->PickableOff();
  this->Label->GetTextProperty()->SetFontSize(13);
  this->Label->GetTextProperty()->SetColor(1, 1, 1);
  this->Label->GetTextProperty()->SetJustificationToCentered();
  this->Label->PickableOff();
  renderer->AddActor2D(this->Bar);
  renderer->AddActor2D(this->Label);
  this->RenderCallback->SetClientData(this);
  this->RenderCallback->SetCallback(&qTissueMosaicViewLegends::onRender);
  this->RenderObserver = renderer->AddObserver(vtkCommand::StartEvent, this->RenderCallback);

  vtkNew<vtkAxesActor> axes;
  axes->SetShaftTypeToCylinder();
  for (vtkCaptionActor2D* caption : {axes->GetXAxisCaptionActor2D(), axes->GetYAxisCaptionActor2D(),
                                     axes->GetZAxisCaptionActor2D()}) {
    caption->GetCaptionTextProperty()->ShadowOff();
    caption->GetCaptionTextProperty()->ItalicOff();
  }
  this->Axes->SetOrientationMarker(axes);
  this->Axes->SetViewport(0.0, 0.0, 0.12, 0.18);
  if (interactor) {
    this->Axes->SetInteractor(interactor);
    this->Axes->SetEnabled(1);
    this->Axes->InteractiveOff();  // a click in the corner is a click in the view (picking), not a drag of the axes
  }
}

qTissueMosaicViewLegends::~qTissueMosaicViewLegends() {
  this->Renderer->RemoveObserver(this->RenderObserver);
  if (this->Axes->GetInteractor()) this->Axes->SetEnabled(0);
}

std::string qTissueMosaicViewLegends::scaleBarLabel() const {
  return this->Label->GetInput() ? this->Label->GetInput() : "";
}

vtkOrientationMarkerWidget* qTissueMosaicViewLegends::axes() const { return this->Axes; }

void qTissueMosaicViewLegends::onRender(vtkObject*, unsigned long, void* clientData, void*) {
  static_cast<qTissueMosaicViewLegends*>(clientData)->updateScaleBar();
}

void qTissueMosaicViewLegends::updateScaleBar() {
  const int* size = this->Renderer->GetSize();
  vtkCamera* camera = this->Renderer->GetActiveCamera();
  if (!size || size[1] <= 0 || !camera) return;
  // Millimetres per pixel in the plane of the focal point.
  const double viewHeightMm = camera->GetParallelProjection()
                                  ? 2 * camera->GetParallelScale()
                                  : 2 * camera->GetDistance() * std::tan(camera->GetViewAngle() * kPi / 360.0);
  const double mmPerPx = viewHeightMm / size[1];
  if (!(mmPerPx > 0) || !std::isfinite(mmPerPx)) return;
  this->BarLengthMm = roundLength(kTargetBarPx * mmPerPx);
  const double lengthPx = this->BarLengthMm / mmPerPx;
  const double right = size[0] - 24, left = right - lengthPx, y = 16, tick = 5;
  const double points[6][2] = {{left, y}, {right, y}, {left, y - tick}, {left, y + tick}, {right, y - tick}, {right, y + tick}};
  for (int i = 0; i < 6; ++i) this->BarPoints->SetPoint(i, points[i][0], points[i][1], 0);
  this->BarPoints->Modified();
  char text[32];
  std::snprintf(text, sizeof text, this->BarLengthMm >= 1 ? "%.0f mm" : "%.2g mm", this->BarLengthMm);
  this->Label->SetInput(text);
  this->Label->SetDisplayPosition(static_cast<int>((left + right) / 2), static_cast<int>(y + tick + 3));
}
