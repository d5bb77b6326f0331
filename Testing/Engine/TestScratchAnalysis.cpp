// SCRATCH (not to be committed): where the model's far points are.
#include "SyntheticBreathing.h"
#include "SyntheticInstruments.h"
#include "SyntheticScan.h"
#include "TissueSurface.h"
#include "IO/PointCloudPly.h"
#include "IO/MeshPly.h"
#include <gtest/gtest.h>
#include <cstdlib>
#include <cmath>
using namespace tissuemosaic;
TEST(Scratch, DISABLED_Analyse) {
  synthetic::SyntheticScanOptions o;
  o.frames = 300; o.seed = 3;
  o.hardMode.breathingAmplitudeMm = 2; o.hardMode.instruments = 2; o.hardMode.cameraOutStart = 150; o.hardMode.cameraOutEnd = 180;
  const synthetic::SyntheticScan scan(o);
  const ColoredPointCloud cloud = readPly(std::getenv("TM_MODEL"));
  const std::vector<int> frames = scan.tissueFrames();
  std::vector<int> sparse; for (std::size_t i = 0; i < frames.size(); i += 1) sparse.push_back(frames[i]);
  double s2[4] = {0,0,0,0}; std::size_t n[4] = {0,0,0,0}, nearInstrument = 0, breathing = 0;
  const char* names[4] = {"on static surface (<=1mm)", "far, breathing region", "far, near instrument", "far, other"};
  for (const cv::Point3f& p : cloud.pointsMm) {
    const double d = scan.surface().distanceMm(p.x, p.y, p.z);
    const double peak = scan.breathing().peakDisplacementMm(p.x, p.y);
    breathing += peak > 0.01;
    int c = 0;
    if (d > 1.0) {
      const double di = scan.instruments().distanceMm(cv::Vec3d(p.x, p.y, p.z), sparse);
      if (di <= 1.0) { c = 2; ++nearInstrument; } else if (peak > 0.01) c = 1; else c = 3;
    }
    s2[c] += d * d; ++n[c];
  }
  double total = s2[0]+s2[1]+s2[2]+s2[3];
  std::printf("%zu points, %zu in breathing region, %zu far near instrument; rmse to rest surface %.3f\n", cloud.size(), breathing, nearInstrument, std::sqrt(total / cloud.size()));
  for (int c = 0; c < 4; ++c) std::printf("%-28s %8zu points, rms %.3f, contribution to ms %.4f\n", names[c], n[c], n[c] ? std::sqrt(s2[c]/n[c]) : 0.0, s2[c]/cloud.size());
}
