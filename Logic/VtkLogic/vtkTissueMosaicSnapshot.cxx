#include "vtkTissueMosaicSnapshot.h"

#include "IO/AtomicFile.h"
#include "vtkTissueMosaicDisplay.h"
#include "vtkTissueMosaicFrusta.h"
#include "vtkTissueMosaicModelScene.h"
#include "vtkTissueMosaicPointCloud.h"

#include "Core/Error.h"
#include "Reconstruction/ReconstructionPipeline.h"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkPNGWriter.h>
#include <vtkPolyData.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkWindowToImageFilter.h>

#include <filesystem>
#include <sstream>

namespace tissuemosaic {

namespace {

/// The "OpenGL renderer string: ..." line of ReportCapabilities.
std::string rendererLine(vtkRenderWindow* window) {
  auto* openGl = vtkOpenGLRenderWindow::SafeDownCast(window);
  if (!openGl) return "unknown (not an OpenGL render window)";
  const char* capabilities = openGl->ReportCapabilities();
  std::istringstream lines(capabilities ? capabilities : "");
  const std::string key = "OpenGL renderer string:";
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind(key, 0) == 0) {
      const std::size_t start = line.find_first_not_of(' ', key.size());
      return start == std::string::npos ? std::string() : line.substr(start);
    }
  }
  return "unknown";
}

vtkSmartPointer<vtkRenderWindow> offscreenWindow(int widthPx, int heightPx) {
  require(widthPx >= 16 && heightPx >= 16 && widthPx <= 8192 && heightPx <= 8192,
          "snapshot size " + std::to_string(widthPx) + "x" + std::to_string(heightPx) + " px is out of range");
  auto window = vtkSmartPointer<vtkRenderWindow>::New();
  window->SetDisplayId(sharedXConnection());  // VTK's own XOpenDisplay aborts the process when it fails
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);  // identical pictures on every Mesa: no driver-dependent multisampling
  window->SetSize(widthPx, heightPx);
  return window;
}

}  // namespace

vtkSmartPointer<vtkImageData> renderSnapshot(vtkPolyData* model, vtkPolyData* keyFrameFrusta, vtkPolyData* cameraPath,
                                             const SnapshotOptions& options, SnapshotReport* report) {
  // A private Xvfb when one is installed: an offscreen picture never depends on (or shows on) a shared display. On
  // a display shared by parallel test processes, offscreen windows now and then failed to connect.
  const XDisplayStatus display = ensureXDisplay(/*preferPrivate=*/true);
  auto window = offscreenWindow(options.widthPx, options.heightPx);
  vtkNew<vtkRenderer> renderer;
  window->AddRenderer(renderer);
  vtkNew<vtkTissueMosaicModelScene> scene;
  scene->SetModel(model);
  scene->SetKeyFrameFrusta(keyFrameFrusta);
  scene->SetTrajectory(cameraPath);
  scene->AddToRenderer(renderer);
  vtkTissueMosaicModelScene::ResetScopeView(renderer, scene->GetModelActor());
  if (options.pointSizePx > 0) scene->SetPointSizePx(options.pointSizePx);
  else scene->FitPointSizeToView(renderer);
  require(window->SupportsOpenGL() != 0, "the X display " + display.display +
                                             " gives no OpenGL 3.2 context (VTK needs it; Mesa's llvmpipe has it)");
  window->Render();

  vtkNew<vtkWindowToImageFilter> grabber;
  grabber->SetInput(window);
  grabber->SetInputBufferTypeToRGB();
  grabber->ReadFrontBufferOff();
  grabber->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(grabber->GetOutput());

  if (report) {
    report->modelPoints = model ? static_cast<long long>(model->GetNumberOfVerts()) : 0;
    report->keyFrames = keyFrameFrusta ? static_cast<int>(keyFrameFrusta->GetNumberOfLines() / 8) : 0;
    double bounds[6];
    renderer->ComputeVisiblePropBounds(bounds);
    std::copy(bounds, bounds + 6, report->boundsMm.begin());
    report->renderer = rendererLine(window);
    report->display = display.description;
  }
  return image;
}

SnapshotReport writeSnapshotPng(const std::string& pngPath, vtkPolyData* model, vtkPolyData* keyFrameFrusta,
                                vtkPolyData* cameraPath, const SnapshotOptions& options) {
  SnapshotReport report;
  vtkSmartPointer<vtkImageData> image = renderSnapshot(model, keyFrameFrusta, cameraPath, options, &report);
  writeFileAtomically(pngPath, "snapshot", [&](const std::string& temporaryPath) {
    vtkNew<vtkPNGWriter> writer;
    writer->SetFileName(temporaryPath.c_str());
    writer->SetInputData(image);
    writer->Write();
    return writer->GetErrorCode() == 0;
  });
  return report;
}

SnapshotReport writeReconstructionSnapshotPng(const std::string& pngPath, const ReconstructionPipeline& pipeline,
                                              const SnapshotOptions& options) {
  const ModelPoints model = pipeline.modelSnapshot();
  CameraPoses cameras;
  for (const KeyFramePose& keyFrame : pipeline.keyFrames()) {
    CameraPose camera;
    camera.frameIndex = keyFrame.frameIndex;
    camera.T_world_camera = keyFrame.T_world_camera;
    cameras.push_back(camera);
  }
  vtkSmartPointer<vtkPolyData> modelData = pointCloudToPolyData(model.cloud);
  vtkSmartPointer<vtkPolyData> frusta = cameraFrustaToPolyData(cameras, pipeline.geometry(), options.frustumDepthMm);
  vtkNew<vtkPolyData> path;
  updateCameraPath(path, cameras);
  return writeSnapshotPng(pngPath, modelData, frusta, path, options);
}

std::string openGlRendererName() {
  ensureXDisplay(/*preferPrivate=*/true);
  auto window = offscreenWindow(64, 64);
  vtkNew<vtkRenderer> renderer;
  window->AddRenderer(renderer);
  window->Render();
  return rendererLine(window);
}

}  // namespace tissuemosaic
