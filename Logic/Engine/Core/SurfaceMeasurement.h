#pragma once
/// @file SurfaceMeasurement.h
/// @brief One stereo frame as a surface seen from the left rectified camera: per pixel the 3D point, its normal and
/// its colour. Key-frame refinement (the ICP term's q_i and n_i, paper eq. ICPterm) and TSDF fusion both read it.
#include "Core/Device.h"
#include "Core/Float3.h"
#include "Core/Image.h"
#include "Core/PixelFormat.h"
#include "Core/StereoRig.h"

#include <opencv2/core.hpp>

#include <limits>
#include <memory>

namespace tissuemosaic {

/// The point and normal maps where measureSurface computed them on CUDA: refinement and fusion on the same device
/// read them there instead of taking 12 MB per 960x540 frame down to the host and up again.
struct SurfaceMapsOnDevice {
  Image<Float3> pointsCameraMm;
  Image<Float3> normalsCamera;
  /// SurfaceMeasurement::colourBgr (3 bytes a pixel, row-major), uploaded where the surface is measured, which the
  /// pipeline does beside the key frame's matching: fusion then copies it on the device.
  Buffer<uint8_t> colourBgr;
};

/// All maps have the rectified image size; "no estimate" is NaN in every channel.
struct SurfaceMeasurement {
  cv::Mat pointsCameraMm;  ///< CV_32FC3: X Y Z in the left rectified camera frame (x right, y down, z forward), mm;
                           ///< empty when the maps were kept on the device only (see onDevice)
  cv::Mat normalsCamera;   ///< CV_32FC3: unit normals in the same frame, turned toward the camera (n . p < 0)
  cv::Mat colourBgr;       ///< CV_8UC3: the rectified left image
  cv::Mat validMask;       ///< CV_8U: 255 where the pixel has both a point and a normal
  int validPixels = 0;     ///< pixels with both a point and a normal
  /// The same point and normal maps in device memory, when measured on CUDA (else null).
  std::shared_ptr<const SurfaceMapsOnDevice> onDevice;

  bool empty() const { return pointsCameraMm.empty() && !onDevice; }
  bool hasHostMaps() const { return !pointsCameraMm.empty(); }
  /// The rectified image size, from whichever maps exist.
  cv::Size size() const;
  /// validMask, or (for a measurement assembled by hand without one) 255 where the host normals are finite.
  cv::Mat validPixelMask() const;
  /// The point and normal maps on the host, downloaded from the device when only it has them.
  void hostMaps(cv::Mat& pointsCameraMm, cv::Mat& normalsCamera) const;
};

/// Whether host point and normal maps can be read: CV_32FC3, non-empty, of one size.
bool usableHostMaps(const cv::Mat& pointsCameraMm, const cv::Mat& normalsCamera);

/// Copies point and normal maps into `points` and `normals` (allocated by the caller at the maps' size, on either
/// device): from `onDevice` when it is given and the target is on CUDA or the host maps are not usable, else from the
/// host maps. The one rule by which fusion and the refinement's solver take a measurement's maps. Throws Error when
/// neither source can be used or the sizes differ.
void copySurfaceMaps(const cv::Mat& hostPointsCameraMm, const cv::Mat& hostNormalsCamera,
                     const SurfaceMapsOnDevice* onDevice, Image<Float3>& points, Image<Float3>& normals);

/// Where measureSurface leaves the point and normal maps when it runs on CUDA.
enum class SurfaceMapResidence {
  HostAndDevice,  ///< downloaded into the cv::Mat fields as well
  DeviceOnly,     ///< only the valid-pixel mask comes down (0.5 MB instead of 12 MB at 960x540)
};

/// Disparities a measurement keeps: the others count as missing (e.g. the depth range fusion works in).
struct DisparityRangePx {
  float lowestPx = -std::numeric_limits<float>::infinity();
  float highestPx = std::numeric_limits<float>::infinity();
};

namespace surface {
struct Reprojection;
}
/// The geometry's Q as the per-pixel kernels take it (Core/SurfaceKernels.h). Throws Error without a 4x4 CV_64F Q.
surface::Reprojection reprojectionOf(const RectifiedGeometry& geometry);

/// Builds the measurement from a left-view disparity (CV_32F, NaN = none) and the rectified left image (8-bit grey,
/// BGR or BGRA, same size): points as disparityToDepthMm / reconstructScene, normals from the cross product of the
/// central differences of the neighbouring points `normalRadiusPx` away (NaN where a neighbour is missing or the
/// depth jumps by more than `maxDepthJumpMm`). Runs on `device`; on CUDA the maps also stay on the device
/// (`onDevice`), and `residence` says whether they come to the host too. A disparity outside `kept` counts as
/// missing (tested in the kernel: no masked copy of the disparity on the host). Throws Error on empty or mismatched
/// inputs. colourBgr shares the left image's pixels when it is continuous BGR (a cv::Mat header, no copy); an RGB
/// image (`order`) is converted into it, once per measurement (the pipeline measures at key frames only).
SurfaceMeasurement measureSurface(const cv::Mat& disparityPx, const cv::Mat& leftRectified,
                                  const RectifiedGeometry& geometry, Device device, int normalRadiusPx = 2,
                                  double maxDepthJumpMm = 2.0,
                                  SurfaceMapResidence residence = SurfaceMapResidence::HostAndDevice,
                                  DisparityRangePx kept = {}, ChannelOrder order = ChannelOrder::Bgr);
/// The same from a disparity map already in `device`'s memory (e.g. StereoMatcher::lastDisparityAwayFromHighlightsView
/// on CUDA): nothing to upload. The map is read during the call only.
SurfaceMeasurement measureSurface(ImageView<const float> disparityPx, const cv::Mat& leftRectified,
                                  const RectifiedGeometry& geometry, Device device, int normalRadiusPx = 2,
                                  double maxDepthJumpMm = 2.0,
                                  SurfaceMapResidence residence = SurfaceMapResidence::HostAndDevice,
                                  DisparityRangePx kept = {}, ChannelOrder order = ChannelOrder::Bgr);

}  // namespace tissuemosaic
