#include "TissueSurface.h"

#include "SyntheticRandom.h"

#include <cmath>
#include <limits>

namespace tissuemosaic::synthetic {

namespace {
constexpr double twoPi = 6.283185307179586;
// Largest |d/dr| of the bump profile (1 - r^2/s^2)^3, in units of amplitude / radius (at r = s / sqrt(5)).
constexpr double bumpSlopeFactor = 1.7173;
}  // namespace

TissueSurface::TissueSurface(const TissueSurfaceParameters& parameters, uint32_t seed) : parameters_(parameters) {
  std::mt19937 generator(seed ^ 0x5u);
  for (int i = 0; i < parameters.bumpCount; ++i) {
    Bump bump;
    bump.x = uniform(generator, -parameters.extentMm, parameters.extentMm);
    bump.y = uniform(generator, -parameters.extentMm, parameters.extentMm);
    const double radius = uniform(generator, 12.0, 30.0);
    bump.inverseRadius2 = 1.0 / (radius * radius);
    // Keep each bump's slope below 0.3 whatever its radius.
    const double amplitude = std::min(parameters.reliefMm, 0.3 * radius / bumpSlopeFactor);
    bump.amplitude = uniform(generator, -amplitude, amplitude);
    bumps_.push_back(bump);
  }
  for (int i = 0; i < parameters.undulationCount; ++i) {
    Bump bump;
    bump.x = uniform(generator, -parameters.extentMm, parameters.extentMm);
    bump.y = uniform(generator, -parameters.extentMm, parameters.extentMm);
    const double radius = uniform(generator, 5.0, 10.0);
    bump.inverseRadius2 = 1.0 / (radius * radius);
    const double amplitude = std::min(parameters.undulationMm, 0.15 * radius / bumpSlopeFactor);
    bump.amplitude = uniform(generator, -amplitude, amplitude);
    bumps_.push_back(bump);
  }
  // Bin each bump into every grid cell its support touches (support radius <= 30 mm).
  gridCellMm_ = 8.0;
  gridOriginMm_ = -parameters.extentMm - 32.0;
  gridCells_ = static_cast<int>(std::ceil(2.0 * (parameters.extentMm + 32.0) / gridCellMm_));
  grid_.assign(static_cast<std::size_t>(gridCells_) * gridCells_, {});
  for (const Bump& bump : bumps_) {
    const double radius = 1.0 / std::sqrt(bump.inverseRadius2);
    const int x0 = std::max(0, static_cast<int>(std::floor((bump.x - radius - gridOriginMm_) / gridCellMm_)));
    const int x1 = std::min(gridCells_ - 1, static_cast<int>(std::floor((bump.x + radius - gridOriginMm_) / gridCellMm_)));
    const int y0 = std::max(0, static_cast<int>(std::floor((bump.y - radius - gridOriginMm_) / gridCellMm_)));
    const int y1 = std::min(gridCells_ - 1, static_cast<int>(std::floor((bump.y + radius - gridOriginMm_) / gridCellMm_)));
    for (int gy = y0; gy <= y1; ++gy)
      for (int gx = x0; gx <= x1; ++gx) grid_[static_cast<std::size_t>(gy) * gridCells_ + gx].push_back(bump);
  }
  // The dome is >= 0, so the hollows bound h from below.
  minHeightMm_ = 0;
  for (const Bump& bump : bumps_) minHeightMm_ -= std::max(0.0, -bump.amplitude);
}

double TissueSurface::maxSlope(const cv::Rect2d& domain) const {
  constexpr double stepMm = 0.25;
  double largest2 = 0;
  for (double y = domain.y; y <= domain.y + domain.height + stepMm; y += stepMm) {
    for (double x = domain.x; x <= domain.x + domain.width + stepMm; x += stepMm) {
      double gx = 0, gy = 0;
      heightMm(x, y, &gx, &gy);
      largest2 = std::max(largest2, gx * gx + gy * gy);
    }
  }
  // Between samples the slope can grow by at most curvature * step / sqrt(2) (curvatures here are < 0.2 / mm).
  return std::sqrt(largest2) + 0.2 * stepMm;
}

double TissueSurface::distanceMm(double xMm, double yMm, double zMm) const {
  double dhdx = 0, dhdy = 0;
  const double h = heightMm(xMm, yMm, &dhdx, &dhdy);
  return std::abs(zMm - h) / std::sqrt(1 + dhdx * dhdx + dhdy * dhdy);
}

double TissueSurface::heightMm(double x, double y, double* dhdx, double* dhdy) const {
  if (!slide_.active()) return materialHeightMm(x, y, dhdx, dhdy);
  double wx = 0, wy = 0;
  const double w = slide_.shape.weight(x, y, &wx, &wy);
  const double sx = slide_.displacementMm[0], sy = slide_.displacementMm[1];
  double gx = 0, gy = 0;
  const double h = materialHeightMm(x - sx * w, y - sy * w, &gx, &gy);
  // Chain rule through q = p - s w(p): dq/dp = I - s grad(w)^T.
  if (dhdx) *dhdx = gx * (1 - sx * wx) - gy * sy * wx;
  if (dhdy) *dhdy = -gx * sx * wy + gy * (1 - sy * wy);
  return h;
}

double TissueSurface::materialHeightMm(double x, double y, double* dhdx, double* dhdy) const {
  const double s2 = parameters_.domeRadiusMm * parameters_.domeRadiusMm;
  const double root = std::sqrt(1.0 + (x * x + y * y) / s2);
  double h = parameters_.domeDepthMm * (root - 1.0);
  double gx = parameters_.domeDepthMm * x / (s2 * root);
  double gy = parameters_.domeDepthMm * y / (s2 * root);
  const int cellX = static_cast<int>(std::floor((x - gridOriginMm_) / gridCellMm_));
  const int cellY = static_cast<int>(std::floor((y - gridOriginMm_) / gridCellMm_));
  static const std::vector<Bump> none;
  const std::vector<Bump>& nearby = cellX >= 0 && cellY >= 0 && cellX < gridCells_ && cellY < gridCells_
                                        ? grid_[static_cast<std::size_t>(cellY) * gridCells_ + cellX] : none;
  for (const Bump& bump : nearby) {
    const double dx = x - bump.x, dy = y - bump.y;
    const double q = (dx * dx + dy * dy) * bump.inverseRadius2;
    if (q >= 1.0) continue;
    const double w = 1.0 - q;
    h += bump.amplitude * w * w * w;
    const double slope = -6.0 * bump.amplitude * w * w * bump.inverseRadius2;
    gx += slope * dx;
    gy += slope * dy;
  }
  if (swell_.amplitudeMm != 0) {
    double wx = 0, wy = 0;
    h += swell_.amplitudeMm * swell_.weight(x, y, &wx, &wy);
    gx += swell_.amplitudeMm * wx;
    gy += swell_.amplitudeMm * wy;
  }
  for (const SurfaceSwell& swell : extraSwells_) {
    if (swell.amplitudeMm == 0) continue;
    double wx = 0, wy = 0;
    h += swell.amplitudeMm * swell.weight(x, y, &wx, &wy);
    gx += swell.amplitudeMm * wx;
    gy += swell.amplitudeMm * wy;
  }
  if (dhdx) *dhdx = gx;
  if (dhdy) *dhdy = gy;
  return h;
}

TissueSurface TissueSurface::swollen(const SurfaceSwell& swell) const {
  TissueSurface copy = *this;
  copy.minHeightMm_ = minHeightMm_ - std::abs(swell_.amplitudeMm) - std::abs(swell.amplitudeMm);
  copy.swell_ = swell;
  return copy;
}

TissueSurface TissueSurface::deformed(const SurfaceDeformation& deformation) const {
  TissueSurface copy = *this;
  copy.extraSwells_ = deformation.swells;
  copy.slide_ = deformation.slide;
  // The slide only moves the relief sideways: h keeps its lower bound; each swell can lower it by its amplitude.
  copy.minHeightMm_ = minHeightMm_;
  for (const SurfaceSwell& swell : extraSwells_) copy.minHeightMm_ += std::abs(swell.amplitudeMm);
  for (const SurfaceSwell& swell : deformation.swells) copy.minHeightMm_ -= std::abs(swell.amplitudeMm);
  return copy;
}

cv::Vec2d TissueSurface::materialXYMm(double x, double y) const {
  if (!slide_.active()) return {x, y};
  const double w = slide_.shape.weight(x, y);
  return {x - slide_.displacementMm[0] * w, y - slide_.displacementMm[1] * w};
}

cv::Vec3d TissueSurface::materialPointMm(double restX, double restY) const {
  // p = q + s w(p): a contraction (|s| max|grad w| < 1), so p converges from p = q.
  double x = restX, y = restY;
  for (int iteration = 0; iteration < 100 && slide_.active(); ++iteration) {
    const double w = slide_.shape.weight(x, y);
    const double nextX = restX + slide_.displacementMm[0] * w, nextY = restY + slide_.displacementMm[1] * w;
    const bool converged = std::abs(nextX - x) + std::abs(nextY - y) < 1e-10;
    x = nextX;
    y = nextY;
    if (converged) break;
  }
  return {x, y, heightMm(x, y)};
}

cv::Vec3d TissueSurface::normal(double x, double y) const {
  double gx = 0, gy = 0;
  heightMm(x, y, &gx, &gy);
  return cv::normalize(cv::Vec3d(gx, gy, -1.0));
}

double TissueSurface::intersect(const cv::Vec3d& o, const cv::Vec3d& d, double warmStart, cv::Vec2d* gradient,
                               double toleranceMm) const {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (!(d[2] > 0)) return nan;
  // g(t) = z(t) - h(x(t), y(t)) increases along the ray when slopes are bounded (see maxSlope), so Newton's method
  // safeguarded by a bracket [lo, hi] finds the one root. h >= minHeight gives g(lo) <= 0.
  double lo = std::max(0.0, (minHeightMm_ - o[2]) / d[2]);
  double hi = std::numeric_limits<double>::infinity();
  double t = warmStart > lo ? warmStart : lo;
  for (int iteration = 0; iteration < 60; ++iteration) {
    double gx = 0, gy = 0;
    const double g = o[2] + t * d[2] - heightMm(o[0] + t * d[0], o[1] + t * d[1], &gx, &gy);
    const double dg = d[2] - gx * d[0] - gy * d[1];
    if (g <= 0) lo = t; else hi = t;
    double next = dg > 0 ? t - g / dg : nan;
    if (!(next > lo && next < hi)) next = std::isfinite(hi) ? 0.5 * (lo + hi) : lo + 2.0 * (t - lo) + 10.0;
    if (std::abs(next - t) < toleranceMm) {
      if (gradient) *gradient = cv::Vec2d(gx, gy);  // at t, within the tolerance of the hit
      return next;
    }
    t = next;
  }
  if (gradient) heightMm(o[0] + t * d[0], o[1] + t * d[1], &(*gradient)[0], &(*gradient)[1]);
  return t;
}

}  // namespace tissuemosaic::synthetic
