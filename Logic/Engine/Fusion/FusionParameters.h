#pragma once
/// @file FusionParameters.h
/// @brief Every parameter of the point-based TSDF fusion (paper III.E) and of the surface measurement it reads, in
/// one validated struct. The command line, the parameter files and the GUI panel all edit this object.
namespace cv {
class FileStorage;
class FileNode;
}  // namespace cv

namespace tissuemosaic {

struct FusionParameters {
  // Merging (TSDF running average, no voxel grid).
  double truncationMm = 1.5;          ///< a measurement within this distance along the ray of a model point merges
  double maxWeight = 64.0;            ///< running-average cap: older observations keep at most this weight
  double maxNormalAngleDeg = 75.0;    ///< a model point merges only if its normal and the measured one differ less
  int coverageRadiusPx = 1;           ///< a measured pixel counts as covered when an agreeing model point lands
                                      ///< within this many pixels (Chebyshev), so a revisit adds no second layer

  // Colour weight: 1 in the image centre, falling toward the edges (paper III.E).
  double colourFullWeightFraction = 0.5;  ///< full weight within this fraction of the half-diagonal from the centre
  double colourMinWeight = 0.1;           ///< the weight at the image corners (linear fall between)

  // Model size.
  int maxPoints = 20000000;  ///< point budget: new points are refused once the model holds this many
  int newPointStepPx = 1;             ///< new points only at every k-th pixel in x and y (1 = every pixel)
  /// Not in the paper: a measured pixel whose own model point has been observed at least this many times but
  /// disagrees with it (farther than truncationMm along the ray) is not added as a new point: it is a stereo outlier
  /// (or a surface hidden behind the model), not new surface. Without it, every revisit of a specular or weakly
  /// textured patch adds its few gross stereo errors, and over a 5-minute scan they pile up (RMSE 0.2 -> 2.6 mm on
  /// the synthetic scan). 0: off.
  int conflictMinWeight = 3;

  // Motion (not in the paper): every tracked frame whose model agreement is good (ModelAgreement.h) takes weight
  // from the model points it contradicts, so that tissue that keeps moving (breathing) and what passed in front of
  // it (instruments fused where the model had nothing yet) leave the model, while still tissue keeps its weight.
  /// Weight a model point loses per frame that contradicts it (its merges add 1 per key frame); at 0 it leaves the
  /// model. 0: off.
  double motionPenalty = 1.0;
  /// A frame contradicts a point when its stereo depth at the point's pixel differs by more than
  /// max(motionMinThresholdMm, motionNoiseFactor x the frame's median depth difference to the model): beyond the
  /// frame's own noise and pose error.
  double motionMinThresholdMm = 0.3;
  double motionNoiseFactor = 4.0;
  /// A measurement more than this in front of a point is something passing in front of it (an instrument), not
  /// evidence that the point moved; while motionPenalty > 0, a key frame does not fuse such a measurement either
  /// (instruments in front of fused tissue leave no points).
  double occlusionMarginMm = 3.0;
  /// A point that left the model by motion evidence stays as a marker: a later key frame's measurement within this
  /// distance of it (along its viewing ray) is not fused. Breathing tissue at rest would otherwise be fused again at
  /// every key frame, and leave again, blurring the model between. 0: markers block nothing.
  double movedTissueRadiusMm = 3.0;
  /// A marker whose tissue this many frames in a row (of those that measure it) put back within the motion
  /// threshold of its place is a live point again (weight 1), and key frames merge into it: tissue that an
  /// instrument pushed and let go fills back into the model. One whose tissue they all put elsewhere is retired and
  /// no longer keeps key frames from fusing the tissue where it now rests (a held breath, tissue held aside).
  /// Breathing tissue passes its markers on every breath and leaves them as they are; 300 frames are 10 s at 30 fps,
  /// two breaths at least. 0: markers stay for good.
  int markerRestFrames = 300;
  /// A point fused from one key frame only (weight 1) that this many frames in a row see through leaves the model
  /// and keeps nothing from being fused: their depth at its pixel lies more than occlusionMarginMm in front of it
  /// and is the model's own nearest surface there. A stereo error fused behind the tissue is never measured again
  /// where it lies, and motion evidence reads a measurement in front of a point as an instrument passing, so such
  /// errors stayed for good (1080p synthetic scan, 120 frames: 1 798 points 5-63 mm behind the tissue made the model
  /// RMSE 0.80 mm against a p95 of 0.085). An instrument in front is nearer than the model's surface and gives no such
  /// evidence. 0: off.
  int seenThroughFrames = 5;
  /// Frames whose share of depths within 1 mm of the model is below this give no motion evidence (the pose or the
  /// whole view may be off).
  double motionMinAgreementShare = 0.5;

  /// The scope's working range: measurements nearer or farther than this are not fused (and not used by the
  /// refinement's ICP term). Stereo errors where the eyes' views barely overlap can put points metres away.
  double minDepthMm = 5.0;
  double maxDepthMm = 500.0;
  /// Not in the paper: fit the deformation graph over the model to every tracked frame (docs/DEFORMATION.md): the
  /// live surface, its agreement and the node motions are reported per frame. Not yet fused through the inverse
  /// warp: with it on, the model and the poses are those of the rigid pipeline (off), bit for bit. File value "off" /
  /// "on".
  bool deformation = false;
  // Surface measurement (measureSurface).
  int normalRadiusPx = 2;             ///< normals from neighbours this many pixels away
  double maxDepthJumpMm = 2.0;        ///< no normal where a neighbour's depth differs by more than this

  /// Throws Error naming the first parameter that is out of range.
  void validate() const;

  /// Writes the parameters under the node name "fusion".
  void write(cv::FileStorage& storage) const;
  /// Reads the parameters from a "fusion" node; keys that are missing keep their defaults, keys of the wrong type
  /// are an error. Validates the result.
  static FusionParameters read(const cv::FileNode& fusionNode);
};

}  // namespace tissuemosaic
