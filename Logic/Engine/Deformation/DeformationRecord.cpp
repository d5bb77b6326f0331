#include "Deformation/DeformationRecord.h"

#include "Core/Error.h"

#include <Eigen/Geometry>

#include <cstdio>

namespace tissuemosaic {

DeformationRecordWriter::DeformationRecordWriter(const std::string& path) : path_(path), out_(path, std::ios::trunc) {
  require(out_.good(), "cannot write the deformation record '" + path + "'");
}

void DeformationRecordWriter::write(int frameIndex, double timeS, const DeformationGraph& graph) {
  char number[64];
  out_ << "{\"frame\": " << frameIndex;
  std::snprintf(number, sizeof number, "%.6f", timeS);
  out_ << ", \"time_s\": " << number << ", \"nodes\": [";
  for (int i = 0; i < graph.nodeCount(); ++i) {
    const DeformationNode& node = graph.nodes()[static_cast<std::size_t>(i)];
    const Eigen::AngleAxisd turn(node.rotation);
    const Eigen::Vector3d r = turn.angle() * turn.axis();
    std::snprintf(number, sizeof number, "%s[%.4f, %.4f, %.4f, ", i ? ", " : "", node.positionMm.x(),
                  node.positionMm.y(), node.positionMm.z());
    out_ << number;
    std::snprintf(number, sizeof number, "%.4f, %.4f, %.4f, ", node.translationMm.x(), node.translationMm.y(),
                  node.translationMm.z());
    out_ << number;
    std::snprintf(number, sizeof number, "%.6f, %.6f, %.6f]", r.x(), r.y(), r.z());
    out_ << number;
  }
  out_ << "]}\n";
  out_.flush();
  require(out_.good(), "writing the deformation record '" + path_ + "' failed");
}

}  // namespace tissuemosaic
