#pragma once
/// @file DeformationRecord.h
/// @brief The per-frame deformation for research (`reconstruct --deformation-out F.jsonl`): JSON Lines, one object
/// per tracked frame in order,
///   {"frame": 12, "time_s": 0.4, "nodes": [[gx, gy, gz, tx, ty, tz, rx, ry, rz], ...]}
/// with every node of the graph at that frame (index = the node's stable index): g its rest position, t its motion
/// (world frame, mm; the node now lies at g + t), r its rotation as a rotation vector (radians, axis times angle).
/// Frames without a fit (lost, no model yet) are left out. Docs: docs/DEFORMATION.md.
#include "Deformation/DeformationGraph.h"

#include <fstream>
#include <string>

namespace tissuemosaic {

class DeformationRecordWriter {
public:
  /// Opens (truncates) path. Throws Error when it cannot be written.
  explicit DeformationRecordWriter(const std::string& path);
  /// Appends one frame's line and flushes it (a stopped scan keeps every frame written). Throws Error on a failed write.
  void write(int frameIndex, double timeS, const DeformationGraph& graph);

private:
  std::string path_;
  std::ofstream out_;
};

}  // namespace tissuemosaic
