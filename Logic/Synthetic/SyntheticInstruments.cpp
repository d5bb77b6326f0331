#include "SyntheticInstruments.h"

#include "Core/Error.h"
#include "SyntheticRandom.h"
#include "SyntheticRenderer.h"
#include "TissueSurface.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tissuemosaic::synthetic {

namespace {

constexpr double pi = 3.141592653589793;
constexpr double degree = pi / 180.0;
constexpr double kRetractedMm = 70.0;  ///< how far back along the shaft the tip starts and ends (out of view)
constexpr double kTrocarLateralMm = 90.0, kTrocarHeightMm = 120.0;

double smoothstep(double a, double b, double x) {
  const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

/// Closest point of the segment a-b to p, as the fraction along it.
double closestFraction(const cv::Vec3d& a, const cv::Vec3d& b, const cv::Vec3d& p) {
  const cv::Vec3d ab = b - a;
  const double length2 = ab.dot(ab);
  return length2 > 0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
}

/// Ray (unit direction) against a capsule: the distance along the ray to the first hit in front of the origin, or
/// -1. The cylinder's side first, then the end balls.
double intersectCapsule(const cv::Vec3d& origin, const cv::Vec3d& unit, const Capsule& capsule) {
  const cv::Vec3d ba = capsule.toMm - capsule.fromMm, oa = origin - capsule.fromMm;
  const double baba = ba.dot(ba), bard = ba.dot(unit), baoa = ba.dot(oa), rdoa = unit.dot(oa), oaoa = oa.dot(oa);
  const double r2 = capsule.radiusMm * capsule.radiusMm;
  const double a = baba - bard * bard, b = baba * rdoa - baoa * bard, c = baba * oaoa - baoa * baoa - r2 * baba;
  double h = b * b - a * c;
  if (h < 0) return -1;
  if (a > 1e-12) {
    const double t = (-b - std::sqrt(h)) / a;
    const double y = baoa + t * bard;
    if (y > 0 && y < baba) return t > 0 ? t : -1;
  }
  // The end balls: the one the side test points at, then the other (a ray along the axis meets only balls).
  double best = -1;
  for (const cv::Vec3d& centre : {capsule.fromMm, capsule.toMm}) {
    const cv::Vec3d oc = origin - centre;
    const double bb = unit.dot(oc), cc = oc.dot(oc) - r2;
    h = bb * bb - cc;
    if (h <= 0) continue;
    const double t = -bb - std::sqrt(h);
    if (t > 0 && (best < 0 || t < best)) best = t;
  }
  return best;
}

/// Which part of an instrument a ray met, and where.
struct PartHit {
  double distanceMm = std::numeric_limits<double>::infinity();  ///< along the unit ray
  const InstrumentPose* pose = nullptr;
  int part = -1;  ///< 0 shaft, 1 and 2 jaws
};

PartHit firstHit(const std::vector<InstrumentPose>& poses, const cv::Vec3d& origin, const cv::Vec3d& unit) {
  PartHit hit;
  for (const InstrumentPose& pose : poses) {
    const Capsule* parts[3] = {&pose.shaft, &pose.jaws[0], &pose.jaws[1]};
    for (int k = 0; k < 3; ++k) {
      const double t = intersectCapsule(origin, unit, *parts[k]);
      if (t > 0 && t < hit.distanceMm) hit = {t, &pose, k};
    }
  }
  return hit;
}

/// Linear BGR reflectance of a part at a surface point: brushed steel with two dark marking bands on the shaft
/// near the tip, darker jaws with serrations across them (edges that feature detectors find, as on real tools).
cv::Vec3d albedoAt(const InstrumentPose& pose, int part, const cv::Vec3d& pointMm) {
  if (part == 0) {
    const double along = (pointMm - pose.tipMm).dot(pose.axis);
    if ((along > 7 && along < 9.5) || (along > 16 && along < 17.5) || (along > 24 && along < 30)) {
      return {0.05, 0.05, 0.05};
    }
    return {0.40, 0.38, 0.37};
  }
  const Capsule& jaw = pose.jaws[static_cast<std::size_t>(part - 1)];
  const double along = cv::norm(pointMm - jaw.fromMm);
  return std::fmod(along, 1.6) < 0.8 ? cv::Vec3d(0.18, 0.18, 0.19) : cv::Vec3d(0.42, 0.42, 0.44);
}

}  // namespace

double Capsule::distanceMm(const cv::Vec3d& pointMm) const {
  const double f = closestFraction(fromMm, toMm, pointMm);
  return cv::norm(pointMm - (fromMm + f * (toMm - fromMm))) - radiusMm;
}

bool InstrumentOccluder::shade(const cv::Vec3d& origin, const cv::Vec3d& direction, double tMax,
                               const ShadingParameters& shading, cv::Vec3d& radianceBgr) const {
  if (poses_.empty()) return false;
  const double scale = cv::norm(direction);
  const cv::Vec3d unit = direction / scale;
  const PartHit hit = firstHit(poses_, origin, unit);
  if (!hit.pose || !(hit.distanceMm < tMax * scale)) return false;
  const Capsule& capsule = hit.part == 0 ? hit.pose->shaft : hit.pose->jaws[static_cast<std::size_t>(hit.part - 1)];
  const cv::Vec3d point = origin + hit.distanceMm * unit;
  const cv::Vec3d onAxis = capsule.fromMm + closestFraction(capsule.fromMm, capsule.toMm, point) *
                                                (capsule.toMm - capsule.fromMm);
  const cv::Vec3d normal = cv::normalize(point - onAxis);
  cv::Vec3d toLight = shading.lightWorldMm - point;
  const double distance2 = toLight.dot(toLight);
  toLight *= 1.0 / std::sqrt(distance2);
  const cv::Vec3d toEye = -unit;
  const double diffuse = std::max(0.0, normal.dot(toLight));
  const double halfway = std::max(0.0, normal.dot(cv::normalize(toLight + toEye)));
  // Brushed steel: a broad sheen and a sharp highlight along the shaft, both much larger than wet tissue's.
  double h2 = halfway * halfway, h4 = h2 * h2, h8 = h4 * h4, h16 = h8 * h8, h32 = h16 * h16;
  const double specular = 0.25 * h32 + 1.0 * h32 * h32 * h32 * h32;
  const double irradiance = shading.lightReferenceMm * shading.lightReferenceMm / distance2;
  const cv::Vec3d albedo = albedoAt(*hit.pose, hit.part, point);
  const double lit = (diffuse + shading.ambient) * irradiance;
  radianceBgr = lit * albedo + cv::Vec3d::all(specular * irradiance);
  return true;
}

bool InstrumentOccluder::hits(const cv::Vec3d& origin, const cv::Vec3d& direction) const {
  return !poses_.empty() && firstHit(poses_, origin, cv::normalize(direction)).pose != nullptr;
}

SyntheticInstruments::SyntheticInstruments(int count, int frames, double fps, uint32_t seed,
                                           const std::function<bool(int, cv::Vec3d&)>& viewCentreMm,
                                           const TissueSurface& highest, const cv::Vec2d& borderReachMm)
    : fps_(fps) {
  require(count >= 0 && frames > 0 && fps > 0, "synthetic instruments: invalid count, frames or frame rate");
  std::mt19937 generator(seed ^ 0x1257u);
  const double firstAzimuth = uniform(generator, 0, 2 * pi);
  for (int i = 0; i < count; ++i) {
    Plan plan;
    plan.instrument = i;
    plan.highest = &highest;
    const double start = 0.05 + 0.5 * i / count + uniform(generator, -0.02, 0.02);
    plan.enter = std::clamp(static_cast<int>(std::lround(start * frames)), 0, frames - 1);
    plan.leave = std::clamp(plan.enter + std::max(2, static_cast<int>(std::lround(0.4 * frames))), plan.enter + 1,
                            frames - 1);
    // Around where the scope looks in the middle of the span (the nearest frame with tissue), a little off centre.
    cv::Vec3d centre;
    const int middle = (plan.enter + plan.leave) / 2;
    bool found = false;
    for (int step = 0; step < frames && !found; ++step) {
      for (int index : {middle - step, middle + step}) {
        if (!found && index >= 0 && index < frames && viewCentreMm(index, centre)) found = true;
      }
    }
    require(found, "synthetic instruments: no frame shows tissue");
    const double offsetX = uniform(generator, -8, 8), offsetY = uniform(generator, -5, 5);
    const double azimuth = firstAzimuth + 2 * pi * i / std::max(count, 1) + uniform(generator, -0.3, 0.3);
    plan.anchorMm = {centre[0] + offsetX, centre[1] + offsetY};
    if (borderReachMm[0] != 0 || borderReachMm[1] != 0) {
      // Near the border on the trocar's side: the shaft crosses little of the view. The random offset shrinks
      // with the reach so that the tip stays in view.
      plan.anchorMm = {centre[0] + borderReachMm[0] * std::cos(azimuth) + 0.25 * offsetX,
                       centre[1] + borderReachMm[1] * std::sin(azimuth) + 0.25 * offsetY};
    }
    plan.trocarMm = {plan.anchorMm[0] + kTrocarLateralMm * std::cos(azimuth),
                     plan.anchorMm[1] + kTrocarLateralMm * std::sin(azimuth),
                     highest.heightMm(plan.anchorMm[0], plan.anchorMm[1]) - kTrocarHeightMm};
    for (int k = 0; k < 2; ++k) {
      plan.wanderMm[k] = uniform(generator, 4, 9);
      plan.wanderOmega[k] = 2 * pi / uniform(generator, 2.5, 5.0);
      plan.wanderPhase[k] = uniform(generator, 0, 2 * pi);
    }
    plan.hoverMm = uniform(generator, 9, 13);
    plan.hoverOmega = 2 * pi / uniform(generator, 3, 6);
    plan.hoverPhase = uniform(generator, 0, 2 * pi);
    plan.jawOmega = 2 * pi / uniform(generator, 1.2, 2.4);
    plan.jawPhase = uniform(generator, 0, 2 * pi);
    plan.rollOmega = 2 * pi / uniform(generator, 4, 8);
    plan.rollPhase = uniform(generator, 0, 2 * pi);
    plans_.push_back(plan);
  }
}

std::pair<int, int> SyntheticInstruments::span(int instrument) const {
  require(instrument >= 0 && instrument < count(), "synthetic instruments: no instrument " + std::to_string(instrument));
  return {plans_[static_cast<std::size_t>(instrument)].enter, plans_[static_cast<std::size_t>(instrument)].leave};
}

double SyntheticInstruments::spanFraction(int instrument, int index, double offsetS) const {
  const Plan& plan = plans_.at(static_cast<std::size_t>(instrument));
  return (static_cast<double>(index - plan.enter) + offsetS * fps_) / std::max(1, plan.leave - plan.enter);
}

InstrumentPose SyntheticInstruments::pose(const Plan& plan, int index, double offsetS) const {
  const double t = index / fps_ + offsetS;
  const double u = (static_cast<double>(index - plan.enter) + offsetS * fps_) / std::max(1, plan.leave - plan.enter);
  // In along the shaft over the first 15 % of the span, out over the last 15 %.
  const double inserted = smoothstep(0.0, 0.15, u) * (1 - smoothstep(0.85, 1.0, u));
  const cv::Vec2d xy = plan.anchorMm + cv::Vec2d(plan.wanderMm[0] * std::sin(plan.wanderOmega[0] * t + plan.wanderPhase[0]),
                                                 plan.wanderMm[1] * std::sin(plan.wanderOmega[1] * t + plan.wanderPhase[1]));
  const double hover = plan.hoverMm + 3.0 * std::sin(plan.hoverOmega * t + plan.hoverPhase);
  const cv::Vec3d target(xy[0], xy[1], plan.highest->heightMm(xy[0], xy[1]) - hover);
  InstrumentPose pose;
  pose.instrument = plan.instrument;
  pose.axis = cv::normalize(plan.trocarMm - target);
  pose.tipMm = target + (1 - inserted) * kRetractedMm * pose.axis;
  // Jaws open 0-40 degrees in a plane through the shaft that turns slowly about it.
  const double opening = (20.0 + 20.0 * std::sin(plan.jawOmega * t + plan.jawPhase)) * degree;
  const double roll = 0.6 * std::sin(plan.rollOmega * t + plan.rollPhase);
  const cv::Vec3d e1 = cv::normalize(pose.axis.cross(cv::Vec3d(0, 0, 1)));
  const cv::Vec3d e2 = pose.axis.cross(e1);
  const cv::Vec3d hinge = std::cos(roll) * e1 + std::sin(roll) * e2;
  const auto place = [&](cv::Vec3d tip) {
    pose.tipMm = tip;
    pose.shaft = {tip, plan.trocarMm, kShaftRadiusMm};
    for (int j = 0; j < 2; ++j) {
      const double side = j == 0 ? 1.0 : -1.0;
      const cv::Vec3d direction = std::cos(0.5 * opening) * (-pose.axis) + side * std::sin(0.5 * opening) * hinge;
      pose.jaws[static_cast<std::size_t>(j)] = {tip, tip + kJawLengthMm * direction, kJawRadiusMm};
    }
  };
  place(pose.tipMm);
  // Lift the whole instrument (toward the scope) where a part would come nearer the tissue than the clearance.
  double deficit = 0;
  const auto check = [&](const Capsule& capsule, double lengthMm) {
    const cv::Vec3d d = cv::normalize(capsule.toMm - capsule.fromMm);
    for (double s = 0; s <= lengthMm; s += 0.5) {
      const cv::Vec3d p = capsule.fromMm + s * d;
      const double gap = plan.highest->heightMm(p[0], p[1]) - p[2] - capsule.radiusMm;
      deficit = std::max(deficit, kClearanceMm - gap);
    }
  };
  check(pose.shaft, 40.0);
  check(pose.jaws[0], kJawLengthMm + kJawRadiusMm);
  check(pose.jaws[1], kJawLengthMm + kJawRadiusMm);
  if (deficit > 0) place(pose.tipMm - cv::Vec3d(0, 0, deficit + 0.01));
  return pose;
}

std::vector<InstrumentPose> SyntheticInstruments::posesAt(int index, double offsetS) const {
  std::vector<InstrumentPose> poses;
  for (const Plan& plan : plans_) {
    if (index >= plan.enter && index <= plan.leave) poses.push_back(pose(plan, index, offsetS));
  }
  return poses;
}

namespace {

/// A capsule as triangles: `sides` around, the end balls as hemispheres of `rings` latitude rings each.
void appendCapsule(TriangleMesh& mesh, const Capsule& capsule, int sides = 16, int rings = 4) {
  const cv::Vec3d axis = cv::normalize(capsule.toMm - capsule.fromMm);
  const cv::Vec3d helper = std::abs(axis[2]) < 0.9 ? cv::Vec3d(0, 0, 1) : cv::Vec3d(1, 0, 0);
  const cv::Vec3d e1 = cv::normalize(axis.cross(helper)), e2 = axis.cross(e1);
  const double r = capsule.radiusMm;
  // Rings from the `from` pole to the `to` pole: latitude angles -90..0 at `from`, 0..90 at `to`.
  std::vector<std::pair<cv::Vec3d, double>> ringCentreRadius;
  for (int k = 1; k <= rings; ++k) {
    const double a = -0.5 * pi + 0.5 * pi * k / rings;
    ringCentreRadius.emplace_back(capsule.fromMm + r * std::sin(a) * axis, r * std::cos(a));
  }
  for (int k = 0; k < rings; ++k) {
    const double a = 0.5 * pi * k / rings;
    ringCentreRadius.emplace_back(capsule.toMm + r * std::sin(a) * axis, r * std::cos(a));
  }
  const int base = static_cast<int>(mesh.verticesMm.size());
  const auto point = [](const cv::Vec3d& p) {
    return cv::Point3f(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]));
  };
  mesh.verticesMm.push_back(point(capsule.fromMm - r * axis));  // base: the `from` pole
  for (const auto& [centre, radius] : ringCentreRadius) {
    for (int s = 0; s < sides; ++s) {
      const double phi = 2 * pi * s / sides;
      mesh.verticesMm.push_back(point(centre + radius * (std::cos(phi) * e1 + std::sin(phi) * e2)));
    }
  }
  const int topPole = static_cast<int>(mesh.verticesMm.size());
  mesh.verticesMm.push_back(point(capsule.toMm + r * axis));
  const int ringCount = static_cast<int>(ringCentreRadius.size());
  const auto ring = [&](int k, int s) { return base + 1 + k * sides + (s % sides); };
  for (int s = 0; s < sides; ++s) mesh.triangles.emplace_back(base, ring(0, s + 1), ring(0, s));
  for (int k = 0; k + 1 < ringCount; ++k) {
    for (int s = 0; s < sides; ++s) {
      mesh.triangles.emplace_back(ring(k, s), ring(k, s + 1), ring(k + 1, s + 1));
      mesh.triangles.emplace_back(ring(k, s), ring(k + 1, s + 1), ring(k + 1, s));
    }
  }
  for (int s = 0; s < sides; ++s) mesh.triangles.emplace_back(topPole, ring(ringCount - 1, s), ring(ringCount - 1, s + 1));
}

Capsule meshedShaft(const InstrumentPose& pose) {
  Capsule shaft = pose.shaft;
  const double length = cv::norm(shaft.toMm - shaft.fromMm);
  if (length > SyntheticInstruments::kMeshedShaftLengthMm) {
    shaft.toMm = shaft.fromMm + (SyntheticInstruments::kMeshedShaftLengthMm / length) * (shaft.toMm - shaft.fromMm);
  }
  return shaft;
}

}  // namespace

TriangleMesh SyntheticInstruments::surfaceMesh(const std::vector<int>& frames) const {
  TriangleMesh mesh;
  for (int index : frames) {
    for (const InstrumentPose& pose : posesAt(index)) {
      appendCapsule(mesh, meshedShaft(pose));
      appendCapsule(mesh, pose.jaws[0]);
      appendCapsule(mesh, pose.jaws[1]);
    }
  }
  return mesh;
}

double SyntheticInstruments::distanceMm(const cv::Vec3d& pointMm, const std::vector<int>& frames) const {
  double nearest = std::numeric_limits<double>::infinity();
  for (int index : frames) {
    for (const InstrumentPose& pose : posesAt(index)) {
      nearest = std::min({nearest, meshedShaft(pose).distanceMm(pointMm), pose.jaws[0].distanceMm(pointMm),
                          pose.jaws[1].distanceMm(pointMm)});
    }
  }
  return nearest;
}

}  // namespace tissuemosaic::synthetic
