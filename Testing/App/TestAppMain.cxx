// Test driver main for the desktop application: the window needs OpenGL, so the tests run on an X display (a
// private Xvfb when there is none), with one QApplication for all tests.
#include "vtkTissueMosaicDisplay.h"

#include <QVTKOpenGLNativeWidget.h>
#include <gtest/gtest.h>

#include <QApplication>
#include <QSurfaceFormat>

#include <cstdlib>
#include <iostream>

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  try {
    std::cout << "[ display  ] " << tissuemosaic::ensureXDisplay().description << std::endl;
  } catch (const std::exception& error) {
    std::cerr << error.what() << std::endl;
    return 1;
  }
  setenv("QT_QPA_PLATFORM", "xcb", 1);
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication application(argc, argv);
  return RUN_ALL_TESTS();
}
