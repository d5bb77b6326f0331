// The in-vivo mode of the synthetic scans (SyntheticInVivo.h) against its own ground truth: the depth maps lie on
// each frame's true surface and the written surface_NNNNNN.ply projects onto them; the pulsation and the push move
// only their own patch, by their amplitude, and a pressing instrument touches the tissue without passing through it;
// the lateral breathing carries the texture with the tissue; interlaced fields and motion blur are renders at their
// instants; --in-vivo builds a still-scope scan at 360x288 and 960x540; with every new option off the frames are
// bit for bit those of the generator before the mode.
#include "ErrorText.h"
#include "SyntheticBreathing.h"
#include "SyntheticCapture.h"
#include "SyntheticInVivo.h"
#include "SyntheticInstruments.h"
#include "SyntheticPulse.h"
#include "SyntheticPush.h"
#include "SyntheticScan.h"
#include "TissueSurface.h"

#include "Core/Error.h"
#include "IO/MeshPly.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <tuple>
#include <vector>

using namespace tissuemosaic;
using namespace tissuemosaic::synthetic;

namespace {

/// A small still-scope scan whose tissue deforms in every in-vivo way (no blur, no fields: one instant a frame).
SyntheticScanOptions deformingScan() {
  SyntheticScanOptions options;
  options.width = 200;
  options.height = 160;
  options.frames = 24;
  options.seed = 5;
  options.supersampling = 1;
  options.minSpeedMmPerS = options.maxSpeedMmPerS = 0;
  options.maxTiltDeg = options.maxRollDeg = 0;
  options.minWorkingDistanceMm = options.maxWorkingDistanceMm = 80;
  options.hardMode.breathingAmplitudeMm = 2;
  options.hardMode.breathingPeriodS = 0.8;  // a peak at frame 12 (0.4 s)
  options.hardMode.breathingRadiusMm = 100;
  options.hardMode.instruments = 1;
  options.inVivo.breathingLateralMm = 1.5;
  options.inVivo.pulseAmplitudeMm = 0.8;
  options.inVivo.pulsePeriodS = 0.8;  // a peak at frame 12 too
  options.inVivo.pushMm = 2;
  return options;
}

/// The world point seen at left pixel (u, v) with depth z at the pose T.
Eigen::Vector3d backProject(const RectifiedGeometry& g, const Eigen::Matrix4d& T, double u, double v, double z) {
  const Eigen::Vector3d camera((u - g.cxLeftPx) * z / g.focalPx, (v - g.cyPx) * z / g.focalPx, z);
  return T.block<3, 3>(0, 0) * camera + T.block<3, 1>(0, 3);
}

/// 64-bit FNV-1a over a matrix's bytes, continued from `hash`.
uint64_t fnv1a(const cv::Mat& m, uint64_t hash) {
  const cv::Mat c = m.isContinuous() ? m : m.clone();
  const auto* bytes = c.ptr<uint8_t>();
  for (std::size_t i = 0; i < c.total() * c.elemSize(); ++i) hash = (hash ^ bytes[i]) * 1099511628211ull;
  return hash;
}

/// Every image and truth map of a frame, hashed.
uint64_t frameHash(const SyntheticScanFrame& f) {
  uint64_t hash = 14695981039346656037ull;
  for (const cv::Mat* m : {&f.leftRectified, &f.rightRectified, &f.disparityPx, &f.depthMm, &f.highlightMaskLeft,
                           &f.instrumentMask}) {
    if (!m->empty()) hash = fnv1a(*m, hash);
  }
  return hash;
}

/// Bit for bit the same (NaN included).
bool sameBits(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
}

bool sameRows(const cv::Mat& a, const cv::Mat& b, int parity) {
  for (int y = parity; y < a.rows; y += 2) {
    if (std::memcmp(a.ptr(y), b.ptr(y), a.cols * a.elemSize()) != 0) return false;
  }
  return true;
}

}  // namespace

// The frames of the generator before the in-vivo mode (commit e304fb7, this toolchain: GCC, x86-64-v3,
// -ffp-contract=off), hashed: the mode's options off must leave every pixel and truth value as it was.
TEST(SyntheticInVivo, WithTheNewOptionsOffTheFramesAreBitForBitThoseOfBefore) {
  SyntheticScanOptions plain;
  plain.width = 160;
  plain.height = 120;
  plain.frames = 3;
  plain.seed = 11;
  SyntheticScanOptions hard = plain;
  hard.frames = 6;
  hard.seed = 5;
  hard.hardMode.breathingAmplitudeMm = 2;
  hard.hardMode.breathingPeriodS = 1;
  hard.hardMode.instruments = 2;
  hard.hardMode.smoke = true;
  hard.lighting = SyntheticLighting::Realistic;
  const SyntheticScan plainScan(plain), hardScan(hard);
  EXPECT_EQ(frameHash(plainScan.renderFrame(0)), 0x7498e3c37fef0be8ull);
  EXPECT_EQ(frameHash(plainScan.renderFrame(2)), 0x4db9cf6c6faf5a89ull);
  EXPECT_EQ(frameHash(hardScan.renderFrame(1)), 0x9c8ead72649fb60cull);
  EXPECT_EQ(frameHash(hardScan.renderFrame(4)), 0xc75b97adbfbf172eull);
  // The options spelled out as off are the defaults.
  SyntheticScanOptions off = plain;
  off.inVivo = SyntheticInVivoOptions{};
  off.inVivo.breathingLateralMm = 0;
  off.inVivo.motionBlurMs = 0;
  off.inVivo.interlaced = false;
  EXPECT_EQ(frameHash(SyntheticScan(off).renderFrame(2)), frameHash(plainScan.renderFrame(2)));
}

TEST(SyntheticInVivo, TheDepthLiesOnEachFramesTrueSurfaceAndTheWrittenMeshProjectsOntoIt) {
  const SyntheticScan scan(deformingScan());
  const RectifiedGeometry& g = scan.geometry();
  const TriangleMesh rest = scan.seenSurfaceMesh(0.5, 4);
  for (int k : {0, 7, 12, 18}) {
    const SyntheticScanFrame frame = scan.renderFrame(k);
    const TissueSurface truth = scan.surfaceAt(k);
    // Every 4th pixel back-projected with the true pose lies on the frame's true surface.
    double worstMm = 0;
    int samples = 0;
    for (int v = 1; v < frame.depthMm.rows; v += 4) {
      for (int u = 1; u < frame.depthMm.cols; u += 4) {
        const float z = frame.depthMm.at<float>(v, u);
        if (!std::isfinite(z)) continue;
        const Eigen::Vector3d p = backProject(g, frame.T_world_camera, u, v, z);
        worstMm = std::max(worstMm, std::abs(p.z() - truth.heightMm(p.x(), p.y())));
        // The disparity is the depth's: f B / Z - doffs.
        EXPECT_NEAR(frame.disparityPx.at<float>(v, u), g.focalPx * g.baselineMm / z - g.doffsPx, 1e-3);
        ++samples;
      }
    }
    EXPECT_GT(samples, 1500) << k;
    EXPECT_LT(worstMm, 1e-3) << k;  // float depth: about 1e-5 mm at 80 mm
    // surface_NNNNNN.ply's vertices (the rest mesh moved with the tissue) projected into the left view: the depth
    // map there (bilinear between pixel centres) is their depth.
    const TriangleMesh now = scan.frameSurfaceMesh(rest, k);
    ASSERT_EQ(now.verticesMm.size(), rest.verticesMm.size());
    const Eigen::Matrix4d T = frame.T_world_camera;
    std::vector<double> errors;
    for (std::size_t i = 0; i < now.verticesMm.size(); i += 7) {
      const cv::Point3f& w = now.verticesMm[i];
      const Eigen::Vector3d c = T.block<3, 3>(0, 0).transpose() * (Eigen::Vector3d(w.x, w.y, w.z) - T.block<3, 1>(0, 3));
      const double u = g.focalPx * c.x() / c.z() + g.cxLeftPx, v = g.focalPx * c.y() / c.z() + g.cyPx;
      if (u < 1 || v < 1 || u > g.imageSize.width - 2 || v > g.imageSize.height - 2) continue;
      cv::Mat sample;
      cv::getRectSubPix(frame.depthMm, {1, 1}, cv::Point2f(static_cast<float>(u), static_cast<float>(v)), sample);
      const float z = sample.at<float>(0, 0);
      if (std::isfinite(z)) errors.push_back(std::abs(z - c.z()));
    }
    ASSERT_GT(errors.size(), 300u) << k;
    std::sort(errors.begin(), errors.end());
    EXPECT_LT(errors[errors.size() / 2], 0.01) << k;
    EXPECT_LT(errors.back(), 0.1) << k;
    // And each moved vertex lies on the frame's surface; at rest it is where rest_surface.ply has it.
    for (std::size_t i = 0; i < now.verticesMm.size(); i += 97) {
      const cv::Point3f& w = now.verticesMm[i];
      EXPECT_NEAR(w.z, truth.heightMm(w.x, w.y), 1e-3);
    }
  }
}

TEST(SyntheticInVivo, ThePulseMovesOnlyItsPatchByItsAmplitude) {
  SyntheticScanOptions options = deformingScan();
  options.hardMode.breathingAmplitudeMm = 0;
  options.inVivo.breathingLateralMm = 0;
  options.hardMode.instruments = 0;
  options.inVivo.pushMm = 0;
  const SyntheticScan scan(options);
  ASSERT_TRUE(scan.pulse().active());
  const SurfaceSwell& shape = scan.pulse().shape();
  EXPECT_DOUBLE_EQ(shape.outerRadiusMm, options.inVivo.pulseRadiusMm);
  // Frame 12 is 0.4 s: the beat's peak. Its centre rose by the whole amplitude toward the scope (-Z) ...
  const cv::Vec3d centre = scan.displacementMm(shape.centreXMm, shape.centreYMm, 12);
  EXPECT_NEAR(centre[2], -options.inVivo.pulseAmplitudeMm, 1e-9);
  EXPECT_NEAR(std::hypot(centre[0], centre[1]), 0, 1e-12);
  // ... at frame 6 (a quarter beat) by half of it; at frame 0 not at all.
  EXPECT_NEAR(scan.displacementMm(shape.centreXMm, shape.centreYMm, 6)[2], -0.5 * options.inVivo.pulseAmplitudeMm, 1e-9);
  EXPECT_EQ(scan.displacementMm(shape.centreXMm, shape.centreYMm, 0)[2], 0);
  // Nothing beyond its radius moves, and nothing moves more than the amplitude.
  const TissueSurface peak = scan.surfaceAt(12);
  const cv::Rect2d d = scan.scannedDomainMm();
  double largestMm = 0;
  for (double y = d.y; y < d.y + d.height; y += 0.5) {
    for (double x = d.x; x < d.x + d.width; x += 0.5) {
      const double moved = scan.surface().heightMm(x, y) - peak.heightMm(x, y);
      largestMm = std::max(largestMm, std::abs(moved));
      if (std::hypot(x - shape.centreXMm, y - shape.centreYMm) >= shape.outerRadiusMm) ASSERT_EQ(moved, 0) << x << " " << y;
    }
  }
  EXPECT_NEAR(largestMm, options.inVivo.pulseAmplitudeMm, 1e-9);
  // The patch is in view: the left view's depth there is nearer by the amplitude than at rest.
  const SyntheticScanFrame atRest = scan.renderFrame(0), atPeak = scan.renderFrame(12);
  double nearerMm = 0;
  for (int v = 0; v < atRest.depthMm.rows; ++v)
    for (int u = 0; u < atRest.depthMm.cols; ++u)
      nearerMm = std::max(nearerMm, double(atRest.depthMm.at<float>(v, u) - atPeak.depthMm.at<float>(v, u)));
  EXPECT_NEAR(nearerMm, options.inVivo.pulseAmplitudeMm, 0.05);
}

TEST(SyntheticInVivo, AnInstrumentPressesADentThatFollowsItsJawsAndMovesNothingElse) {
  SyntheticScanOptions options = deformingScan();
  options.hardMode.breathingAmplitudeMm = 0;
  options.inVivo.breathingLateralMm = 0;
  options.inVivo.pulseAmplitudeMm = 0;
  const SyntheticScan scan(options);
  const auto [enter, leave] = scan.instruments().span(0);
  int pressing = 0;
  double deepestMm = 0;
  for (int k = enter; k <= leave; ++k) {
    const double weight = pushWeight(scan.instruments().spanFraction(0, k));
    const std::vector<SurfaceSwell> dents = scan.pushDentsAt(k);
    if (weight == 0) {
      EXPECT_TRUE(dents.empty()) << k;
      continue;
    }
    if (dents.empty()) continue;  // on its way down, not touching yet
    ++pressing;
    ASSERT_EQ(dents.size(), 1u);
    const SurfaceSwell& dent = dents[0];
    deepestMm = std::max(deepestMm, dent.amplitudeMm);
    const TissueSurface now = scan.surfaceAt(k);
    // The jaws' lowest point is on the dented tissue: touching, not passing through.
    const PressedInstrument pressed = pressInstrument(scan.instruments().posesAt(k)[0], weight, options.inVivo.pushMm,
                                                      scan.surface());
    EXPECT_NEAR(pressed.lowestMm[2], now.heightMm(pressed.lowestMm[0], pressed.lowestMm[1]), 1e-9) << k;
    EXPECT_NEAR(std::hypot(pressed.lowestMm[0] - dent.centreXMm, pressed.lowestMm[1] - dent.centreYMm), 0, 1e-9);
    // The dent goes into the tissue (+Z) by its amplitude at its centre, and nothing beyond its radius moves.
    EXPECT_NEAR(now.heightMm(dent.centreXMm, dent.centreYMm) - scan.surface().heightMm(dent.centreXMm, dent.centreYMm),
                dent.amplitudeMm, 1e-9);
    for (double a = 0; a < 6.28; a += 0.5) {
      for (double r : {dent.outerRadiusMm, dent.outerRadiusMm + 3}) {
        const double x = dent.centreXMm + r * std::cos(a), y = dent.centreYMm + r * std::sin(a);
        EXPECT_EQ(now.heightMm(x, y), scan.surface().heightMm(x, y));
      }
    }
  }
  EXPECT_GE(pressing, 2);
  // At full weight the jaws go pushMm below where they touched (the tissue's slope changes it a little).
  EXPECT_NEAR(deepestMm, options.inVivo.pushMm, 0.3 * options.inVivo.pushMm);
}

TEST(SyntheticInVivo, TheLateralBreathingCarriesTheTissueAndItsTextureSideways) {
  SyntheticScanOptions options = deformingScan();
  options.hardMode.instruments = 0;
  options.inVivo.pushMm = 0;
  options.inVivo.pulseAmplitudeMm = 0;
  const SyntheticScan scan(options);
  const cv::Vec2d direction = scan.breathing().lateralDirection();
  // At the breath's peak (frame 12, 0.4 s) a point of the flat top slid by the lateral amplitude and rose by the
  // breathing's.
  const SurfaceSwell& shape = scan.breathing().shape();
  const cv::Vec3d moved = scan.displacementMm(shape.centreXMm + 3, shape.centreYMm - 2, 12);
  EXPECT_NEAR(moved[0], options.inVivo.breathingLateralMm * direction[0], 1e-9);
  EXPECT_NEAR(moved[1], options.inVivo.breathingLateralMm * direction[1], 1e-9);
  EXPECT_NEAR(moved[2], -options.hardMode.breathingAmplitudeMm, 1e-9);
  // The image follows: the peak frame's left view matches the rest frame's shifted by the slide's image motion
  // (lateral mm x f / Z) far better than unshifted.
  const SyntheticScanFrame rest = scan.renderFrame(0), peak = scan.renderFrame(12);
  const double pixels = options.inVivo.breathingLateralMm * scan.geometry().focalPx / 78.0;
  cv::Mat shifted;
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, pixels * direction[0], 0, 1, pixels * direction[1]);
  cv::warpAffine(rest.leftRectified, shifted, shift, rest.leftRectified.size());
  const cv::Rect inner(20, 20, options.width - 40, options.height - 40);
  cv::Mat a, b, c;
  cv::cvtColor(peak.leftRectified(inner), a, cv::COLOR_BGR2GRAY);
  cv::cvtColor(shifted(inner), b, cv::COLOR_BGR2GRAY);
  cv::cvtColor(rest.leftRectified(inner), c, cv::COLOR_BGR2GRAY);
  EXPECT_LT(cv::norm(a, b, cv::NORM_L1), 0.8 * cv::norm(a, c, cv::NORM_L1));
}

TEST(SyntheticInVivo, InterlacedFieldsAndMotionBlurAreRendersAtTheirInstants) {
  SyntheticScanOptions options = deformingScan();
  options.frames = 16;
  options.hardMode.instruments = 2;  // they move fast enough to blur
  options.inVivo.interlaced = true;
  const SyntheticScan interlaced(options);
  const double half = 0.5 / options.fps;
  for (int k : {5, 8}) {
    const SyntheticScanFrame frame = interlaced.renderFrame(k);
    const SyntheticScanFrame even = interlaced.renderFrameAt(k, 0), odd = interlaced.renderFrameAt(k, half);
    for (const auto& [framed, at, parity] : {std::tuple{&frame.leftRectified, &even.leftRectified, 0},
                                             std::tuple{&frame.rightRectified, &even.rightRectified, 0},
                                             std::tuple{&frame.leftRectified, &odd.leftRectified, 1},
                                             std::tuple{&frame.rightRectified, &odd.rightRectified, 1}}) {
      EXPECT_TRUE(sameRows(*framed, *at, parity)) << k << " parity " << parity;
    }
    EXPECT_FALSE(sameRows(frame.leftRectified, even.leftRectified, 1)) << k;  // the odd field is later
    // The truth is the even field's (the frame's time).
    EXPECT_TRUE(sameBits(frame.depthMm, even.depthMm)) << k;
    EXPECT_FALSE(sameBits(frame.depthMm, odd.depthMm)) << k;
  }
  // Blur: each field the average of the scene over the exposure, centred on the field's time.
  options.inVivo.motionBlurMs = 12;
  const SyntheticScan blurred(options);
  const std::vector<double> instants = exposureOffsetsS(options.inVivo.motionBlurMs);
  ASSERT_EQ(instants.size(), 5u);  // 3 ms apart
  const int k = 8;  // the second instrument (frames 5-11) in the middle of its span
  cv::Mat sum;
  for (int parity : {0, 1}) {
    for (double offset : instants) accumulateField(blurred.renderFrameAt(k, parity * half + offset).leftRectified, parity, sum);
  }
  const SyntheticScanFrame frame = blurred.renderFrame(k);
  EXPECT_EQ(cv::norm(frame.leftRectified, averagedImage(sum, 5), cv::NORM_INF), 0);
  EXPECT_TRUE(sameBits(frame.depthMm, blurred.renderFrameAt(k, 0).depthMm));
  // The instruments smear; the still tissue far from them does not change (its noise is the same at every instant).
  const SyntheticScanFrame sharp = interlaced.renderFrame(k);
  cv::Mat difference;
  cv::absdiff(frame.leftRectified, sharp.leftRectified, difference);
  cv::cvtColor(difference, difference, cv::COLOR_BGR2GRAY);
  EXPECT_GT(cv::countNonZero(difference > 8), 20);
}

TEST(SyntheticInVivo, ThePresetBuildsAStillScopeScanAt360x288And960x540) {
  for (const cv::Size size : {cv::Size(360, 288), cv::Size(960, 540)}) {
    SyntheticScanOptions options;
    options.width = size.width;
    options.height = size.height;
    options.frames = 40;
    options.supersampling = 1;
    applyInVivoPreset(options);
    const SyntheticScan scan(options);
    EXPECT_TRUE(scan.tissueDeforms());
    for (int k = 1; k < scan.frameCount(); ++k) EXPECT_EQ(scan.T_world_camera(k), scan.T_world_camera(0)) << k;
    // The whole view breathes: nothing seen stays still.
    EXPECT_TRUE(scan.staticSurfaceMesh(0.5, 8, true).triangles.empty());
    // The middle of the first instrument's span, where it presses: tissue fills the view,
    // the instrument covers a little of it from the border, and its dent is in view.
    const auto [enter, leave] = scan.instruments().span(0);
    const int k = (enter + leave) / 2;
    ASSERT_FALSE(scan.pushDentsAt(k).empty()) << size;
    const SyntheticScanFrame frame = scan.renderFrame(k);
    EXPECT_GT(cv::countNonZero(frame.depthMm == frame.depthMm), 0.85 * size.area()) << size;
    const int covered = cv::countNonZero(frame.instrumentMask);
    EXPECT_GT(covered, 0.005 * size.area()) << size;
    EXPECT_LT(covered, 0.25 * size.area()) << size;
    const cv::Mat& mask = frame.instrumentMask;
    const int atEdge = cv::countNonZero(mask.row(0)) + cv::countNonZero(mask.row(mask.rows - 1)) +
                       cv::countNonZero(mask.col(0)) + cv::countNonZero(mask.col(mask.cols - 1));
    EXPECT_GT(atEdge, 0) << size << ": the shaft comes in over the image's border";
    const SurfaceSwell dent = scan.pushDentsAt(k)[0];
    const Eigen::Matrix4d T = frame.T_world_camera;
    const TissueSurface now = scan.surfaceAt(k);
    const Eigen::Vector3d w(dent.centreXMm, dent.centreYMm, now.heightMm(dent.centreXMm, dent.centreYMm));
    const Eigen::Vector3d c = T.block<3, 3>(0, 0).transpose() * (w - T.block<3, 1>(0, 3));
    const double u = scan.geometry().focalPx * c.x() / c.z() + scan.geometry().cxLeftPx;
    const double v = scan.geometry().focalPx * c.y() / c.z() + scan.geometry().cyPx;
    EXPECT_TRUE(u > 0 && v > 0 && u < size.width && v < size.height) << size << " " << u << " " << v;
    // The in-vivo look: blood-red.
    const cv::Scalar mean = cv::mean(frame.leftRectified, frame.instrumentMask == 0);
    EXPECT_GT(mean[2], 1.5 * mean[1]) << size;  // red
  }
}

TEST(SyntheticInVivo, WritesTheRestSurfaceAndEveryFramesSurface) {
  const std::filesystem::path folder = std::filesystem::path(TM_TEST_OUTPUT_DIR) / "synthetic_in_vivo";
  std::filesystem::remove_all(folder);
  SyntheticScanOptions options = deformingScan();
  options.frames = 3;
  options.width = 120;
  options.height = 96;
  const SyntheticScan scan(options);
  writeSyntheticScan(scan, folder.string());
  const TriangleMesh rest = readMeshPly((folder / "groundtruth" / "rest_surface.ply").string());
  const TriangleMesh seen = scan.seenSurfaceMesh(0.5);
  ASSERT_EQ(rest.verticesMm.size(), seen.verticesMm.size());
  EXPECT_EQ(rest.triangles.size(), seen.triangles.size());
  for (std::size_t i = 0; i < rest.verticesMm.size(); i += 53) {
    EXPECT_NEAR(rest.verticesMm[i].z, scan.surface().heightMm(rest.verticesMm[i].x, rest.verticesMm[i].y), 1e-4);
  }
  for (int k = 0; k < options.frames; ++k) {
    const std::filesystem::path path = folder / "groundtruth" / cv::format("surface_%06d.ply", k);
    ASSERT_TRUE(std::filesystem::exists(path)) << path;
    const TriangleMesh mesh = readMeshPly(path.string());
    ASSERT_EQ(mesh.verticesMm.size(), rest.verticesMm.size());
    const TissueSurface truth = scan.surfaceAt(k);
    for (std::size_t i = 0; i < mesh.verticesMm.size(); i += 53) {
      EXPECT_NEAR(mesh.verticesMm[i].z, truth.heightMm(mesh.verticesMm[i].x, mesh.verticesMm[i].y), 1e-3);
    }
  }
  EXPECT_FALSE(std::filesystem::exists(folder / "groundtruth" / cv::format("surface_%06d.ply", options.frames)));
  std::filesystem::remove_all(folder);
}

TEST(SyntheticInVivo, RejectsInvalidOptionsWithTheirNames) {
  const auto build = [](SyntheticScanOptions options) { return [options] { SyntheticScan scan(options); }; };
  SyntheticScanOptions options = deformingScan();
  options.hardMode.breathingAmplitudeMm = 0;
  EXPECT_NE(errorOf(build(options)).find("lateral breathing needs breathing"), std::string::npos);
  options = deformingScan();
  options.hardMode.instruments = 0;
  EXPECT_NE(errorOf(build(options)).find("a push needs instruments"), std::string::npos);
  options = deformingScan();
  options.inVivo.pulseAmplitudeMm = 4;
  EXPECT_NE(errorOf(build(options)).find("pulse amplitude"), std::string::npos);
  options = deformingScan();
  options.inVivo.interlaced = true;
  options.inVivo.motionBlurMs = 20;  // a field lasts 16.7 ms at 30 fps
  EXPECT_NE(errorOf(build(options)).find("longer than a field"), std::string::npos);
  options = deformingScan();
  options.hardMode.breathingRadiusMm = 20;
  options.inVivo.breathingLateralMm = 5;  // more strain than the slide allows
  EXPECT_NE(errorOf(build(options)).find("lower --breathing-lateral-mm"), std::string::npos);
  EXPECT_THROW(parseTissueLook("pale"), Error);
}
