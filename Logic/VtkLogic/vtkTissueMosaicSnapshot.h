#pragma once
/// @file vtkTissueMosaicSnapshot.h
/// @brief Offscreen pictures of a reconstruction (model + key-frame frusta + camera path), for headless runs:
/// `tissuemosaic reconstruct ... --snapshot view.png`, the tests and the documentation. Makes sure an X display
/// exists first (ensureXDisplay: a private Xvfb whenever Xvfb is installed, else $DISPLAY). No Qt.
#include <vtkSmartPointer.h>

#include <array>
#include <string>

class vtkImageData;
class vtkPolyData;

namespace tissuemosaic {

class ReconstructionPipeline;

struct SnapshotOptions {
  int widthPx = 1280;
  int heightPx = 800;
  double pointSizePx = 0;        ///< 0: fitted to the view (vtkTissueMosaicModelScene::FitPointSizeToView)
  double frustumDepthMm = 12.0;  ///< how far in front of each key-frame camera its image rectangle is drawn
};

/// What was drawn: numbers a test or a log can check before looking at the picture.
struct SnapshotReport {
  long long modelPoints = 0;          ///< points given to the point mapper (one vertex cell each)
  int keyFrames = 0;                  ///< frusta drawn
  std::array<double, 6> boundsMm{};   ///< of everything drawn (xmin xmax ymin ymax zmin zmax), world frame
  std::string renderer;               ///< the OpenGL renderer string (e.g. "llvmpipe (LLVM 15.0.6, 256 bits)")
  std::string display;                ///< the X display used and why
};

/// Renders the scene offscreen (vtkTissueMosaicModelScene in the scope view) and returns the picture, RGB,
/// widthPx x heightPx (VTK's image order: the first row is the bottom). Any polydata may be null.
/// Throws Error when no X display can be had or the OpenGL context fails.
vtkSmartPointer<vtkImageData> renderSnapshot(vtkPolyData* model, vtkPolyData* keyFrameFrusta, vtkPolyData* cameraPath,
                                             const SnapshotOptions& options = {}, SnapshotReport* report = nullptr);

/// renderSnapshot, written as a PNG file. Throws Error when the file cannot be written.
SnapshotReport writeSnapshotPng(const std::string& pngPath, vtkPolyData* model, vtkPolyData* keyFrameFrusta,
                                vtkPolyData* cameraPath, const SnapshotOptions& options = {});

/// The pipeline's current model, its key-frame frusta and their path, written as a PNG (what
/// `tissuemosaic reconstruct --snapshot` calls at the end of a run).
SnapshotReport writeReconstructionSnapshotPng(const std::string& pngPath, const ReconstructionPipeline& pipeline,
                                              const SnapshotOptions& options = {});

/// The OpenGL "renderer" string of a fresh offscreen render window (after ensureXDisplay), e.g. to report which
/// renderer a measurement used.
std::string openGlRendererName();

}  // namespace tissuemosaic
