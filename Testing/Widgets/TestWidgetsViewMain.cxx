// Test driver main for widgets with a VTK 3D view (label "widgets"). VTK's Debian build renders through
// X11 only, so ctest runs this driver under xvfb-run (Mesa software OpenGL); Qt's offscreen platform has no OpenGL
// context. A VTK warning or error fails the running test.
#include <gtest/gtest.h>

#include <QApplication>
#include <QSurfaceFormat>
#include <QVTKOpenGLNativeWidget.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>

#include <cstdio>
#include <cstdlib>

namespace {

class FailingOutputWindow : public vtkOutputWindow {
public:
  static FailingOutputWindow* New();
  vtkTypeMacro(FailingOutputWindow, vtkOutputWindow);
  void DisplayErrorText(const char* text) override { ADD_FAILURE() << "VTK error: " << text; }
  void DisplayWarningText(const char* text) override { ADD_FAILURE() << "VTK warning: " << text; }
  void DisplayGenericWarningText(const char* text) override { ADD_FAILURE() << "VTK warning: " << text; }
};
vtkStandardNewMacro(FailingOutputWindow);

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  // Listing the tests (ctest's discovery at build time) needs no display.
  if (::testing::GTEST_FLAG(list_tests)) return RUN_ALL_TESTS();
  if (!std::getenv("DISPLAY")) {
    std::fprintf(stderr, "these tests need an X display with OpenGL: run them under `xvfb-run -a` (ctest does)\n");
    return 1;
  }
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication application(argc, argv);
  vtkNew<FailingOutputWindow> window;
  vtkOutputWindow::SetInstance(window);
  const int status = RUN_ALL_TESTS();
  vtkOutputWindow::SetInstance(nullptr);
  return status;
}
