#pragma once
/// @file Float3.h
/// @brief A 3-vector of floats for kernels of both backends (TM_HOST_DEVICE), laid out as a CV_32FC3 pixel, with
/// the few operations the surface and fusion kernels need. Plain IEEE operations in a fixed order (no FMA on either
/// backend, see Logic/Engine/CMakeLists.txt), so the CPU and CUDA results agree bit for bit.
#include "HostDevice.h"

#include <cmath>
#include <cstdint>

namespace tissuemosaic {

struct Float3 {
  float x, y, z;
};

TM_HOST_DEVICE TM_FORCE_INLINE Float3 operator+(Float3 a, Float3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
TM_HOST_DEVICE TM_FORCE_INLINE Float3 operator-(Float3 a, Float3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
TM_HOST_DEVICE TM_FORCE_INLINE Float3 operator*(float s, Float3 a) { return {s * a.x, s * a.y, s * a.z}; }
TM_HOST_DEVICE TM_FORCE_INLINE float dot(Float3 a, Float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
TM_HOST_DEVICE TM_FORCE_INLINE Float3 cross(Float3 a, Float3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
TM_HOST_DEVICE TM_FORCE_INLINE float length(Float3 a) { return sqrtf(dot(a, a)); }
/// True when the value is finite: NaN ("no estimate" in maps) and infinity fail the comparison.
TM_HOST_DEVICE TM_FORCE_INLINE bool isFinite(float v) { return fabsf(v) <= 3.402823466e38f; }
/// True when every component is finite.
TM_HOST_DEVICE TM_FORCE_INLINE bool isFinite(Float3 a) { return isFinite(a.x) && isFinite(a.y) && isFinite(a.z); }
TM_HOST_DEVICE TM_FORCE_INLINE Float3 nanFloat3() {
  const float nan = NAN;
  return {nan, nan, nan};
}

/// A rigid transform y = R x + t in floats (R row-major), for kernels.
struct RigidTransformF {
  float r[9];
  float t[3];

  TM_HOST_DEVICE TM_FORCE_INLINE Float3 rotate(Float3 a) const {
    return {r[0] * a.x + r[1] * a.y + r[2] * a.z, r[3] * a.x + r[4] * a.y + r[5] * a.z,
            r[6] * a.x + r[7] * a.y + r[8] * a.z};
  }
  TM_HOST_DEVICE TM_FORCE_INLINE Float3 operator()(Float3 a) const {
    const Float3 b = rotate(a);
    return {b.x + t[0], b.y + t[1], b.z + t[2]};
  }
};

}  // namespace tissuemosaic
