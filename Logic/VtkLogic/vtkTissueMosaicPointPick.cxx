#include "vtkTissueMosaicPointPick.h"

#include <vtkCamera.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkProp3D.h>
#include <vtkRenderer.h>

#include <algorithm>
#include <cmath>
#include <tuple>

namespace tissuemosaic {

namespace {

/// The square of a point drawn pointSizePx wide covers the cursor.
bool covers(const ScreenPoint& point, double pointSizePx) {
  return std::max(std::abs(point.dxPx), std::abs(point.dyPx)) <= 0.5 * pointSizePx;
}

/// Display position -> VTK view coordinates (x, y in [-1, 1] across the viewport).
void displayToView(vtkRenderer* renderer, double displayX, double displayY, double view[2]) {
  renderer->SetDisplayPoint(displayX, displayY, 0);
  renderer->DisplayToView();
  const double* point = renderer->GetViewPoint();
  view[0] = point[0];
  view[1] = point[1];
}

}  // namespace

bool isBetterPointPick(const ScreenPoint& a, const ScreenPoint& b, double pointSizePx) {
  const bool aCovers = covers(a, pointSizePx), bCovers = covers(b, pointSizePx);
  if (aCovers != bCovers) return aCovers;
  const double aPx = std::hypot(a.dxPx, a.dyPx), bPx = std::hypot(b.dxPx, b.dyPx);
  if (aCovers) return std::tie(a.depth, aPx, a.id) < std::tie(b.depth, bPx, b.id);
  return std::tie(aPx, a.depth, a.id) < std::tie(bPx, b.depth, b.id);
}

vtkIdType pickDrawnPoint(vtkRenderer* renderer, vtkProp3D* prop, vtkPoints* points, double displayX, double displayY,
                         double pointSizePx, double radiusPx) {
  if (!renderer || !prop || !points || points->GetNumberOfPoints() == 0) return -1;
  // Points -> view coordinates, as vtkRenderer::WorldToView does (depth 0..1 between the clipping planes).
  vtkNew<vtkMatrix4x4> pointsToView;
  vtkMatrix4x4::Multiply4x4(
      renderer->GetActiveCamera()->GetCompositeProjectionTransformMatrix(renderer->GetTiledAspectRatio(), 0, 1),
      prop->GetMatrix(), pointsToView);
  // View -> display is linear: the cursor and the view units of one display pixel.
  double cursor[2], oneRight[2], oneUp[2];
  displayToView(renderer, displayX, displayY, cursor);
  displayToView(renderer, displayX + 1, displayY, oneRight);
  displayToView(renderer, displayX, displayY + 1, oneUp);
  const double pxPerViewX = 1.0 / (oneRight[0] - cursor[0]);
  const double pxPerViewY = 1.0 / (oneUp[1] - cursor[1]);

  const double(*m)[4] = pointsToView->Element;
  ScreenPoint best;
  for (vtkIdType id = 0; id < points->GetNumberOfPoints(); ++id) {
    double p[3];
    points->GetPoint(id, p);
    const double w = m[3][0] * p[0] + m[3][1] * p[1] + m[3][2] * p[2] + m[3][3];
    if (!(w > 0)) continue;  // behind the camera
    const double depth = (m[2][0] * p[0] + m[2][1] * p[1] + m[2][2] * p[2] + m[2][3]) / w;
    if (depth < 0 || depth > 1) continue;  // clipped: not drawn
    ScreenPoint candidate;
    candidate.id = id;
    candidate.depth = depth;
    candidate.dxPx = ((m[0][0] * p[0] + m[0][1] * p[1] + m[0][2] * p[2] + m[0][3]) / w - cursor[0]) * pxPerViewX;
    candidate.dyPx = ((m[1][0] * p[0] + m[1][1] * p[1] + m[1][2] * p[2] + m[1][3]) / w - cursor[1]) * pxPerViewY;
    if (std::hypot(candidate.dxPx, candidate.dyPx) > radiusPx) continue;
    if (best.id < 0 || isBetterPointPick(candidate, best, pointSizePx)) best = candidate;
  }
  return best.id;
}

}  // namespace tissuemosaic
