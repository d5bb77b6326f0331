#pragma once
/// @file FusionKernels.h
/// @brief The per-point and per-pixel steps of the point-based TSDF fusion (paper III.E), written once for both
/// backends (TM_HOST_DEVICE). Backend differences are confined to the atomics (Core/PortableAtomics.h), the float
/// bit casts at the top of this file and the prefix sum (FusionPipeline.inl).
///
/// Determinism: every model point is updated by its own thread only (merging is point-centric), the coverage mask
/// is an order-independent union, new points are compacted by a prefix sum in pixel order and the z-buffer keeps
/// the minimum of a (depth, index) key. With -ffp-contract=off / -fmad=false the CPU and CUDA models agree bit for bit.
#include "Core/Float3.h"
#include "Core/HostDevice.h"
#include "Core/Image.h"
#include "Core/PortableAtomics.h"

#include <cstdint>
#include <cstring>

namespace tissuemosaic::fusion {

// ---- the backend-specific primitives ------------------------------------------------------------------------------

TM_HOST_DEVICE TM_FORCE_INLINE uint32_t floatBits(float value) {
#if defined(__CUDA_ARCH__)
  return __float_as_uint(value);
#else
  uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
#endif
}

TM_HOST_DEVICE TM_FORCE_INLINE float floatFromBits(uint32_t bits) {
#if defined(__CUDA_ARCH__)
  return __uint_as_float(bits);
#else
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
#endif
}

// ---- data -----------------------------------------------------------------------------------------------------------

/// Four floats, 16-byte aligned so a GPU thread loads one in a single transaction.
struct alignas(16) Float4 {
  float x, y, z, w;
};

TM_HOST_DEVICE TM_FORCE_INLINE Float3 xyz(Float4 a) { return {a.x, a.y, a.z}; }
/// A model point still in the model (its positionWeight's weight is positive).
TM_HOST_DEVICE TM_FORCE_INLINE bool isLive(Float4 positionWeight) { return positionWeight.w > 0; }
/// The normal's w of a point that left the model by motion evidence (AgreementKernels.h): it stays in the store as a
/// marker of moving tissue, not live (weight 0), so that key frames do not fuse that tissue again (MergeModelPoints).
/// Live points keep their motion evidence there, in [0, 1]. A marker counts there the frames in a row that measured
/// its tissue back at its place (kMovedTissueMarker + n) or elsewhere (-(kMovedTissueMarker + n)):
/// UpdateMotionEvidence.
constexpr float kMovedTissueMarker = 2.0f;
/// The normal's w of a marker whose tissue came to rest elsewhere: it blocks nothing and stays out of the model.
constexpr float kRetiredMarker = -1.0f;
TM_HOST_DEVICE TM_FORCE_INLINE bool isMovedTissueMarker(Float4 positionWeight, Float4 normal) {
  return !isLive(positionWeight) && (normal.w >= kMovedTissueMarker || normal.w <= -kMovedTissueMarker);
}

/// The model on the device, structure of arrays indexed by point.
struct ModelArrays {
  /// world position (mm); w = TSDF weight (merged observations, capped, less what motion took: Fusion/
  /// AgreementKernels.h). A point whose weight reached 0 has left the model: only the fusion's marker rule reads it
  /// (kMovedTissueMarker).
  Float4* positionWeight;
  Float4* normal;          ///< world unit normal; w = motion evidence (AgreementKernels.h), 0 for a new point,
                           ///< kMovedTissueMarker once it left the model
  Float4* colourWeight;    ///< RGB 0..255 (running average); w = accumulated colour weight (capped)
};

/// Where each model point's tissue is now, when the tissue deforms (fusion.deformation, docs/DEFORMATION.md): the
/// model holds every point where it rests (canonical), and point i is now at live = R_i p + t_i, a rigid motion
/// per point (three rows [R | t] per point). Every step that meets a frame (merging, the z-buffer, the samples, the
/// motion evidence) sees the live points, and what a frame changes is taken back to rest by the inverse motion.
/// rows == nullptr: the model does not deform (every point is where it was fused, and nothing is computed).
struct PointWarps {
  const Float4* rows;

  TM_HOST_DEVICE TM_FORCE_INLINE Float3 live(int64_t i, Float3 p) const {
    if (!rows) return p;
    const Float4 a = rows[3 * i], b = rows[3 * i + 1], c = rows[3 * i + 2];
    return {a.x * p.x + a.y * p.y + a.z * p.z + a.w, b.x * p.x + b.y * p.y + b.z * p.z + b.w,
            c.x * p.x + c.y * p.y + c.z * p.z + c.w};
  }
  TM_HOST_DEVICE TM_FORCE_INLINE Float3 liveDirection(int64_t i, Float3 n) const {
    if (!rows) return n;
    const Float4 a = rows[3 * i], b = rows[3 * i + 1], c = rows[3 * i + 2];
    return {a.x * n.x + a.y * n.y + a.z * n.z, b.x * n.x + b.y * n.y + b.z * n.z, c.x * n.x + c.y * n.y + c.z * n.z};
  }
  /// R_i^T (q - t_i): where a live position rests.
  TM_HOST_DEVICE TM_FORCE_INLINE Float3 rest(int64_t i, Float3 q) const {
    if (!rows) return q;
    const Float4 a = rows[3 * i], b = rows[3 * i + 1], c = rows[3 * i + 2];
    return restDirection(i, {q.x - a.w, q.y - b.w, q.z - c.w});
  }
  TM_HOST_DEVICE TM_FORCE_INLINE Float3 restDirection(int64_t i, Float3 n) const {
    if (!rows) return n;
    const Float4 a = rows[3 * i], b = rows[3 * i + 1], c = rows[3 * i + 2];
    return {a.x * n.x + b.x * n.y + c.x * n.z, a.y * n.x + b.y * n.y + c.y * n.z, a.z * n.x + b.z * n.y + c.z * n.z};
  }
};

/// One key frame's measurement on the device (left rectified camera frame, NaN = none).
struct MeasurementView {
  ImageView<const Float3> pointsMm;
  ImageView<const Float3> normals;
  const uint8_t* colourBgr;  ///< 3 bytes per pixel, row-major
};

/// The left rectified pinhole camera: pixel centres at integer coordinates.
struct PinholeCamera {
  float focalPx, cxPx, cyPx;
  int width, height;

  /// Pixel nearest to the projection of pc (camera frame), false behind the camera or outside the image.
  TM_HOST_DEVICE TM_FORCE_INLINE bool project(Float3 pc, int& x, int& y) const {
    if (!(pc.z > 1e-3f)) return false;
    const float u = focalPx * pc.x / pc.z + cxPx, v = focalPx * pc.y / pc.z + cyPx;
    if (!(u > -0.5f && u < width - 0.5f && v > -0.5f && v < height - 0.5f)) return false;
    x = static_cast<int>(floorf(u + 0.5f));
    y = static_cast<int>(floorf(v + 0.5f));
    return x >= 0 && y >= 0 && x < width && y < height;
  }
};

/// One key frame's pose in the forms the kernels need.
struct FramePose {
  RigidTransformF worldToCamera, cameraToWorld;
  Float3 cameraCentreWorld;
};

/// FusionParameters and the geometry as the kernels use them.
struct FusionSettings {
  PinholeCamera camera;
  float truncationMm;
  float maxWeight;
  float minNormalCosine;          ///< cos(maxNormalAngleDeg)
  int coverageRadiusPx;
  int newPointStepPx;
  float colourFullWeightFraction, colourMinWeight;
  float conflictMinWeight;        ///< FusionParameters::conflictMinWeight; 0: off
  /// A measurement this far or more in front of a model point (along the point's viewing ray) is something passing
  /// in front of the tissue (an instrument, smoke): its pixel counts as covered, so it adds no point. 0: off.
  float occluderMarginMm;
  /// A marker whose tissue this many measuring frames in a row put back at its place is live again (weight 1); one
  /// whose tissue they all put elsewhere is retired (kRetiredMarker). 0: markers stay for good.
  int markerRestFrames;
  /// How far each frame that sees through a point of weight 1 (measures occluderMarginMm or more in front of it)
  /// moves its motion evidence toward 1 (seenThroughEvidenceRate(FusionParameters::seenThroughFrames)). 0: off.
  float seenThroughEvidenceRate;
  /// A measurement within this distance (along the ray) of a moved-tissue marker is not fused. 0: off.
  float movedTissueRadiusMm;
};

constexpr uint64_t kEmptyDepthKey = ~uint64_t(0);
/// Below this cosine between a measured normal and the viewing ray, the ray-plane intersection is ill-conditioned
/// and the measured depth is used instead.
constexpr float kMinRayPlaneCosine = 0.2f;

// ---- shared per-point rules ---------------------------------------------------------------------------------------

/// The colour weight of a measurement at pixel (x, y): 1 within colourFullWeightFraction of the half-diagonal from
/// the image centre, falling linearly to colourMinWeight at the corners (the scope's light is brightest in the
/// centre; paper III.E).
TM_HOST_DEVICE TM_FORCE_INLINE float colourWeightAt(int x, int y, const FusionSettings& s) {
  const float centreX = 0.5f * (s.camera.width - 1), centreY = 0.5f * (s.camera.height - 1);
  const float halfDiagonal = sqrtf(centreX * centreX + centreY * centreY);
  if (s.colourFullWeightFraction >= 1.0f || !(halfDiagonal > 0)) return 1.0f;
  const float dx = x - centreX, dy = y - centreY;
  const float radius = sqrtf(dx * dx + dy * dy) / halfDiagonal;
  if (radius <= s.colourFullWeightFraction) return 1.0f;
  const float t = fminf(1.0f, (radius - s.colourFullWeightFraction) / (1.0f - s.colourFullWeightFraction));
  return 1.0f - (1.0f - s.colourMinWeight) * t;
}

/// Where the viewing ray of the model point pc (camera frame) meets the measured surface at one pixel, as a scale
/// of pc: the tangent plane through the measured point q with normal n, or q's depth where the normal is missing
/// or the ray grazes the plane.
TM_HOST_DEVICE TM_FORCE_INLINE float measuredRayScale(Float3 pc, Float3 q, Float3 n, bool hasNormal) {
  if (hasNormal) {
    const float np = dot(n, pc);
    if (np < -kMinRayPlaneCosine * length(pc)) return dot(n, q) / np;
  }
  return q.z / pc.z;
}

/// True when the measurement at pixel (x, y) sees the surface of the model point pc (normal nc, camera frame):
/// within the truncation distance along the viewing ray and with a compatible normal. rayScale: where the ray meets
/// the measured surface (measuredRayScale).
TM_HOST_DEVICE TM_FORCE_INLINE bool measurementAgrees(const MeasurementView& m, int x, int y, Float3 pc, Float3 nc,
                                                      const FusionSettings& s, float& rayScale) {
  const Float3 q = m.pointsMm.at(x, y);
  if (!isFinite(q)) return false;
  const Float3 n = m.normals.at(x, y);
  const bool hasNormal = isFinite(n);
  if (hasNormal && dot(n, nc) < s.minNormalCosine) return false;
  rayScale = measuredRayScale(pc, q, n, hasNormal);
  const float alongRayMm = (rayScale - 1.0f) * length(pc);
  return fabsf(alongRayMm) <= s.truncationMm;
}

/// True when the measured point q (camera frame) lies at least marginMm nearer to the camera than the model point pc
/// along pc's viewing ray (its depth below pc's by marginMm times the ray's length per unit depth).
TM_HOST_DEVICE TM_FORCE_INLINE bool inFrontOf(Float3 q, Float3 pc, float marginMm) {
  if (!isFinite(q) || !(pc.z > 0)) return false;
  return (pc.z - q.z) * length(pc) / pc.z >= marginMm;
}

// ---- kernels ------------------------------------------------------------------------------------------------------

/// Per model point: project it into the key frame; every pixel of its (2r+1)^2 neighbourhood whose measurement
/// agrees with it counts as covered (so a revisit from nearer or farther adds no second layer); its own pixel also
/// counts as covered when it disagrees but the point is well observed (conflictMinWeight); when its own pixel
/// agrees, the point merges: TSDF running average of its position along its viewing ray, of its normal, and of its
/// colour weighted by the centre-to-edge colour weight; weights capped at maxWeight. A moved-tissue marker covers
/// the pixels of its neighbourhood whose measurement lies within movedTissueRadiusMm of it: tissue that moved there
/// before is not fused again (it would leave again, and smear the model meanwhile).
struct MergeModelPoints {
  ModelArrays model;
  PointWarps warps;
  MeasurementView measurement;
  FramePose pose;
  FusionSettings settings;
  uint8_t* covered;  ///< per pixel
  int* mergedCount;

  TM_HOST_DEVICE void operator()(int64_t index) const {
    const Float4 positionWeight = model.positionWeight[index];
    const bool live = isLive(positionWeight);
    if (!live && !(settings.movedTissueRadiusMm > 0 && isMovedTissueMarker(positionWeight, model.normal[index]))) return;
    const Float3 p = warps.live(index, xyz(positionWeight));  // where the tissue is now
    const Float3 pc = pose.worldToCamera(p);
    int px, py;
    if (!settings.camera.project(pc, px, py)) return;
    const int r = settings.coverageRadiusPx, width = settings.camera.width, height = settings.camera.height;
    if (!live) {
      coverNearMarker(pc, px, py, r);
      return;
    }
    const Float3 nWorld = warps.liveDirection(index, xyz(model.normal[index]));
    const Float3 nc = pose.worldToCamera.rotate(nWorld);
    float ownRayScale = 1.0f;
    bool ownAgrees = false;
    for (int y = py - r; y <= py + r; ++y) {
      if (y < 0 || y >= height) continue;
      for (int x = px - r; x <= px + r; ++x) {
        if (x < 0 || x >= width) continue;
        float rayScale;
        if (!measurementAgrees(measurement, x, y, pc, nc, settings, rayScale)) {
          if (settings.occluderMarginMm > 0 && inFrontOf(measurement.pointsMm.at(x, y), pc, settings.occluderMarginMm)) {
            setFlag(covered + static_cast<int64_t>(y) * width + x);
          }
          continue;
        }
        setFlag(covered + static_cast<int64_t>(y) * width + x);
        if (x == px && y == py) {
          ownAgrees = true;
          ownRayScale = rayScale;
        }
      }
    }
    const float weight = positionWeight.w;
    if (!ownAgrees) {
      // A well-observed model point that the measurement contradicts: the pixel is an outlier, not new surface.
      if (settings.conflictMinWeight > 0 && weight >= settings.conflictMinWeight &&
          isFinite(measurement.pointsMm.at(px, py))) {
        setFlag(covered + static_cast<int64_t>(py) * width + px);
      }
      return;
    }

    const float averagedScale = 1.0f + (ownRayScale - 1.0f) / (weight + 1.0f);
    const Float3 centre = pose.cameraCentreWorld;
    const Float3 moved = warps.rest(index, centre + averagedScale * (p - centre));
    model.positionWeight[index] = {moved.x, moved.y, moved.z, fminf(weight + 1.0f, settings.maxWeight)};

    const int64_t pixel = static_cast<int64_t>(py) * width + px;
    const Float3 measuredNormal = measurement.normals[pixel];
    if (isFinite(measuredNormal)) {
      const Float3 sum = weight * nWorld + pose.cameraToWorld.rotate(measuredNormal);
      const float norm = length(sum);
      if (norm > 0) {
        const Float3 n = warps.restDirection(index, (1.0f / norm) * sum);
        model.normal[index] = {n.x, n.y, n.z, model.normal[index].w};  // w: the motion evidence, kept
      }
    }

    const Float4 colour = model.colourWeight[index];
    const float w = colourWeightAt(px, py, settings);
    const uint8_t* bgr = measurement.colourBgr + pixel * 3;
    const float total = colour.w + w;
    model.colourWeight[index] = {(colour.w * colour.x + w * bgr[2]) / total, (colour.w * colour.y + w * bgr[1]) / total,
                                 (colour.w * colour.z + w * bgr[0]) / total, fminf(total, settings.maxWeight)};
    atomicAddInt(mergedCount, 1);
  }

  TM_HOST_DEVICE void coverNearMarker(Float3 pc, int px, int py, int r) const {
    const int width = settings.camera.width, height = settings.camera.height;
    const float rayPerDepth = length(pc) / pc.z;
    for (int y = py - r; y <= py + r; ++y) {
      if (y < 0 || y >= height) continue;
      for (int x = px - r; x <= px + r; ++x) {
        if (x < 0 || x >= width) continue;
        const Float3 q = measurement.pointsMm.at(x, y);
        if (isFinite(q) && fabsf(q.z - pc.z) * rayPerDepth <= settings.movedTissueRadiusMm) {
          setFlag(covered + static_cast<int64_t>(y) * width + x);
        }
      }
    }
  }
};

/// Per pixel: 1 where the measurement (point and normal) is new, i.e. not covered by the model, on the sub-sampling
/// grid; 0 elsewhere. The prefix sum of these flags places the new points.
struct FlagNewPixels {
  MeasurementView measurement;
  const uint8_t* covered;
  int* flags;
  int stepPx;

  TM_HOST_DEVICE void operator()(int64_t index) const {
    const int width = measurement.pointsMm.width;
    const int i = static_cast<int>(index);
    const int y = i / width, x = i - y * width;
    flags[index] = (x % stepPx == 0 && y % stepPx == 0 && !covered[index] && isFinite(measurement.pointsMm[index]) &&
                    isFinite(measurement.normals[index]))
                       ? 1
                       : 0;
  }
};

/// Per pixel: appends the flagged measurement at firstIndex + its prefix-sum offset, for the first `toAdd` of them
/// in pixel order (the rest are refused for the budget).
struct AppendNewPoints {
  ModelArrays model;
  MeasurementView measurement;
  FramePose pose;
  FusionSettings settings;
  const int* flags;
  const int* offsets;
  int64_t firstIndex;
  int toAdd;

  TM_HOST_DEVICE void operator()(int64_t index) const {
    if (!flags[index] || offsets[index] >= toAdd) return;
    const int width = measurement.pointsMm.width;
    const int i = static_cast<int>(index);
    const int y = i / width, x = i - y * width;
    const int64_t target = firstIndex + offsets[index];
    const Float3 p = pose.cameraToWorld(measurement.pointsMm[index]);
    const Float3 n = pose.cameraToWorld.rotate(measurement.normals[index]);
    const uint8_t* bgr = measurement.colourBgr + index * 3;
    model.positionWeight[target] = {p.x, p.y, p.z, 1.0f};
    model.normal[target] = {n.x, n.y, n.z, 0.0f};
    model.colourWeight[target] = {static_cast<float>(bgr[2]), static_cast<float>(bgr[1]), static_cast<float>(bgr[0]),
                                  colourWeightAt(x, y, settings)};
  }
};

/// Copies the first points of one model store into another (the stores grow by doubling).
struct CopyModelPoints {
  ModelArrays from, to;

  TM_HOST_DEVICE void operator()(int64_t index) const {
    to.positionWeight[index] = from.positionWeight[index];
    to.normal[index] = from.normal[index];
    to.colourWeight[index] = from.colourWeight[index];
  }
};

struct ClearDepthKeys {
  uint64_t* keys;
  TM_HOST_DEVICE void operator()(int64_t index) const { keys[index] = kEmptyDepthKey; }
};

/// Per model point: the z-buffer. A point in front of the camera, inside the image and facing it competes for its
/// pixel with the key (depth bits << 32 | index): positive floats order as their bits, so the minimum is the
/// nearest point (lowest index on ties) whatever the order of the threads.
struct ProjectToDepthKeys {
  const Float4* positionWeight;
  const Float4* normal;
  PointWarps warps;
  FramePose pose;
  PinholeCamera camera;
  uint64_t* keys;

  TM_HOST_DEVICE void operator()(int64_t index) const {
    const Float4 point = positionWeight[index];
    if (!isLive(point)) return;
    const Float3 pc = pose.worldToCamera(warps.live(index, xyz(point)));
    int x, y;
    if (!camera.project(pc, x, y)) return;
    if (dot(pose.worldToCamera.rotate(warps.liveDirection(index, xyz(normal[index]))), pc) >= 0) return;  // back-facing: hidden
    const uint64_t key = (static_cast<uint64_t>(floatBits(pc.z)) << 32) | static_cast<uint32_t>(index);
    atomicMinU64(keys + static_cast<int64_t>(y) * camera.width + x, key);
  }
};

/// A regular grid of sample pixels, one per stride x stride cell (its centre, clamped into the image).
struct SampleGrid {
  int width, height, stride;

  TM_HOST_DEVICE int columns() const { return (width + stride - 1) / stride; }
  TM_HOST_DEVICE int rows() const { return (height + stride - 1) / stride; }
  TM_HOST_DEVICE int64_t cellCount() const { return static_cast<int64_t>(columns()) * rows(); }
  TM_HOST_DEVICE int64_t pixelOf(int64_t cell) const {
    const int c = static_cast<int>(cell);
    const int gy = c / columns(), gx = c - gy * columns();
    const int x = gx * stride + stride / 2, y = gy * stride + stride / 2;
    return static_cast<int64_t>(y < height ? y : height - 1) * width + (x < width ? x : width - 1);
  }
};

/// Per grid cell: 1 where its sample pixel holds a visible model point that no recent frame contradicted.
/// A point whose motion evidence (normal.w, AgreementKernels.h) is at least this is not sampled: a recent frame
/// contradicted it, and the refinement's ICP term would pull the pose toward tissue that moved.
constexpr float kMaxSampledMotionEvidence = 0.5f;

struct FlagGridSamples {
  const uint64_t* keys;
  const Float4* normal;
  SampleGrid grid;
  int* flags;
  TM_HOST_DEVICE void operator()(int64_t cell) const {
    const uint64_t key = keys[grid.pixelOf(cell)];
    flags[cell] = key != kEmptyDepthKey && normal[static_cast<uint32_t>(key & 0xffffffffu)].w < kMaxSampledMotionEvidence;
  }
};

/// Per grid cell: writes the visible model point of a flagged cell at its prefix-sum offset.
struct GatherGridSamples {
  const uint64_t* keys;
  SampleGrid grid;
  const int* flags;
  const int* offsets;
  const Float4* positionWeight;
  const Float4* normal;
  PointWarps warps;        ///< the samples are where the tissue is now
  Float4* samplePositions;
  Float4* sampleNormals;

  TM_HOST_DEVICE void operator()(int64_t cell) const {
    if (!flags[cell]) return;
    const uint32_t point = static_cast<uint32_t>(keys[grid.pixelOf(cell)] & 0xffffffffu);
    const Float4 p = positionWeight[point], n = normal[point];
    const Float3 pLive = warps.live(point, xyz(p)), nLive = warps.liveDirection(point, xyz(n));
    samplePositions[offsets[cell]] = {pLive.x, pLive.y, pLive.z, p.w};
    sampleNormals[offsets[cell]] = {nLive.x, nLive.y, nLive.z, n.w};
  }
};

}  // namespace tissuemosaic::fusion
