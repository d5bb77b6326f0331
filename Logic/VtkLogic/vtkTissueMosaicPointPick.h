#pragma once
/// @file vtkTissueMosaicPointPick.h
/// @brief Picking a point of a point cloud as the user sees it: the point drawn under the cursor.
///
/// Why not vtkPointPicker: for 1000 points or more VTK 9.1 searches in threads (vtkSMPTools) and keeps, of the
/// threads' answers, the one nearest the camera, while each thread keeps the one nearest the ray: which point wins
/// depends on how the points were shared out among the threads, so the same click on the same view picked a
/// neighbouring scan point 0.39 mm away in 9 of 32 runs of the view test on a busy 2-core machine. This pick is one
/// pass in a fixed order with a total ordering of the candidates: the same click always gives the same point.
#include <vtkType.h>

class vtkPoints;
class vtkProp3D;
class vtkRenderer;

namespace tissuemosaic {

/// A point seen from the cursor: its offset on screen (display pixels) and its depth (0 near plane .. 1 far plane).
struct ScreenPoint {
  vtkIdType id = -1;
  double dxPx = 0;
  double dyPx = 0;
  double depth = 0;
};

/// True when `a` is a better pick than `b` for a cursor among points drawn as squares of pointSizePx pixels:
/// a point whose square covers the cursor beats one that does not; of two that cover it, the nearer the camera wins
/// (it is drawn on top); of two that do not, the nearer the cursor on screen, then the nearer the camera; the lower
/// id settles exact ties.
bool isBetterPointPick(const ScreenPoint& a, const ScreenPoint& b, double pointSizePx);

/// The id in `points` of the point drawn under display position (displayX, displayY) (VTK display pixels, origin
/// at the bottom left) when `prop` draws `points` in `renderer` as squares of pointSizePx pixels: by
/// isBetterPointPick among the points within radiusPx pixels of the cursor and inside the clipping range; -1 when
/// there is none. Uses the renderer's current camera and size and the prop's matrix (e.g. a user transform).
vtkIdType pickDrawnPoint(vtkRenderer* renderer, vtkProp3D* prop, vtkPoints* points, double displayX, double displayY,
                         double pointSizePx, double radiusPx);

}  // namespace tissuemosaic
