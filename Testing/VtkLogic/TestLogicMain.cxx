// Test driver main for the logic layer: GoogleTest, plus a VTK output window that turns every VTK warning or
// error into a failure of the test that caused it.
#include <gtest/gtest.h>

#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>

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
  vtkNew<FailingOutputWindow> window;
  vtkOutputWindow::SetInstance(window);
  const int status = RUN_ALL_TESTS();
  vtkOutputWindow::SetInstance(nullptr);
  return status;
}
