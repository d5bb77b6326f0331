// The rectified pinhole camera (Core/PinholeIntrinsics.h): projection against hand-checked pixels, back-projection
// as its inverse, and the Gauss-Newton derivatives against central differences.
#include "Core/PinholeIntrinsics.h"
#include "Core/StereoRig.h"

#include <gtest/gtest.h>

using namespace tissuemosaic;

namespace {
const PinholeIntrinsics kCamera{800.0, 820.0, 480.5, 270.25};
}

TEST(PinholeIntrinsics, ProjectsHandCheckedPoints) {
  double u, v;
  kCamera.project(0.0, 0.0, 50.0, u, v);  // on the optical axis: the principal point
  EXPECT_DOUBLE_EQ(u, 480.5);
  EXPECT_DOUBLE_EQ(v, 270.25);
  kCamera.project(10.0, -5.0, 100.0, u, v);  // 800 * 0.1 + 480.5, 820 * -0.05 + 270.25
  EXPECT_DOUBLE_EQ(u, 560.5);
  EXPECT_DOUBLE_EQ(v, 229.25);
  EXPECT_DOUBLE_EQ(kCamera.normalisedX(560.5), 0.1);
  EXPECT_DOUBLE_EQ(kCamera.normalisedY(229.25), -0.05);
}

TEST(PinholeIntrinsics, BackProjectionInvertsProjection) {
  for (const double z : {20.0, 75.0, 240.0}) {
    for (const double uPx : {0.0, 123.25, 959.0}) {
      for (const double vPx : {0.0, 300.5, 539.0}) {
        double x, y, u, v;
        kCamera.backProject(uPx, vPx, z, x, y);
        kCamera.project(x, y, z, u, v);
        EXPECT_NEAR(u, uPx, 1e-9);
        EXPECT_NEAR(v, vPx, 1e-9);
      }
    }
  }
}

TEST(PinholeIntrinsics, DerivativesMatchCentralDifferences) {
  const double c[3] = {12.0, -7.5, 64.0};
  double u, v, dU[3], dV[3];
  kCamera.projectWithDerivatives(c, u, v, dU, dV);
  double uDivided, vDivided;
  kCamera.project(c[0], c[1], c[2], uDivided, vDivided);
  EXPECT_NEAR(u, uDivided, 1e-9);
  EXPECT_NEAR(v, vDivided, 1e-9);
  const double h = 1e-4;
  for (int k = 0; k < 3; ++k) {
    double plus[3] = {c[0], c[1], c[2]}, minus[3] = {c[0], c[1], c[2]};
    plus[k] += h;
    minus[k] -= h;
    double uPlus, vPlus, uMinus, vMinus;
    kCamera.project(plus[0], plus[1], plus[2], uPlus, vPlus);
    kCamera.project(minus[0], minus[1], minus[2], uMinus, vMinus);
    EXPECT_NEAR(dU[k], (uPlus - uMinus) / (2 * h), 1e-6) << "d u / d c[" << k << "]";
    EXPECT_NEAR(dV[k], (vPlus - vMinus) / (2 * h), 1e-6) << "d v / d c[" << k << "]";
  }
}

TEST(PinholeIntrinsics, RectifiedGeometryGivesTheLeftCamera) {
  RectifiedGeometry geometry;
  geometry.focalPx = 700.0;
  geometry.cxLeftPx = 470.0;
  geometry.cyPx = 260.0;
  geometry.doffsPx = 12.0;  // the right camera's offset must not leak into the left camera
  const PinholeIntrinsics left = geometry.leftIntrinsics();
  EXPECT_EQ(left.fxPx, 700.0);
  EXPECT_EQ(left.fyPx, 700.0);
  EXPECT_EQ(left.cxPx, 470.0);
  EXPECT_EQ(left.cyPx, 260.0);
}
