// Test driver main for the widget layer: one QApplication for all tests (offscreen unless told otherwise).
#include <gtest/gtest.h>

#include <QApplication>

#include <cstdlib>

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  setenv("QT_QPA_PLATFORM", "offscreen", 0);  // keep an explicit choice; needs no X server otherwise
  QApplication application(argc, argv);
  return RUN_ALL_TESTS();
}
