#include "IgtLinkMessages.h"

#include "Core/Error.h"

#include <igtlImageMessage.h>
#include <igtlPolyDataMessage.h>
#include <igtlStatusMessage.h>
#include <igtlTimeStamp.h>
#include <igtlTransformMessage.h>
#include <igtl_header.h>
#include <igtl_polydata.h>
#include <igtl_util.h>

#include <opencv2/imgproc.hpp>

#include <cstdint>
#include <cstring>

namespace tissuemosaic::igtlink {
namespace {

static_assert(std::char_traits<char>::length(kCameraTransformName) <= IGTL_HEADER_NAME_SIZE);
static_assert(std::char_traits<char>::length(kModelName) <= IGTL_HEADER_NAME_SIZE);
static_assert(std::char_traits<char>::length(kStatusName) <= IGTL_HEADER_NAME_SIZE);
static_assert(std::char_traits<char>::length(kVideoName) <= IGTL_HEADER_NAME_SIZE);

void setHeader(igtl::MessageBase* message, const std::string& name, double timeS) {
  require(name.size() <= IGTL_HEADER_NAME_SIZE, "OpenIGTLink device name '" + name + "' is longer than 20 characters");
  message->SetDeviceName(name.c_str());
  igtl::TimeStamp::Pointer stamp = igtl::TimeStamp::New();
  stamp->SetTime(timeS);
  message->SetTimeStamp(stamp);
}

PackedMessage finish(igtl::MessageBase* message, const std::string& type, const std::string& name) {
  message->Pack();
  const auto* data = static_cast<const unsigned char*>(message->GetPackPointer());
  return {type, name, std::make_shared<const std::vector<unsigned char>>(data, data + message->GetPackSize())};
}

/// 1.11's igtl_polydata_pack and _unpack treat POINT_RGBA as a 9-component tensor (upstream handles RGBA since
/// 2017), so the colours are packed as a 4-component POINT_SCALAR and their attribute type byte is set to
/// POINT_RGBA here, with the body's CRC computed again: the wire format is then the protocol's POINT_RGBA.
std::shared_ptr<const std::vector<unsigned char>> markAttributesRgba(std::vector<unsigned char> bytes) {
  auto bigEndian32 = [&](std::size_t at) {
    return static_cast<std::uint32_t>(bytes[at]) << 24 | static_cast<std::uint32_t>(bytes[at + 1]) << 16 |
           static_cast<std::uint32_t>(bytes[at + 2]) << 8 | bytes[at + 3];
  };
  const std::size_t body = IGTL_HEADER_SIZE;
  const std::uint32_t points = bigEndian32(body), attributes = bigEndian32(body + 36);
  // The polydata header (10 x 4 bytes), points, then vertices, lines, polygons and strips, each its size in bytes.
  std::size_t at = body + sizeof(igtl_polydata_header) + 12 * static_cast<std::size_t>(points);
  for (std::size_t size : {8, 16, 24, 32}) at += bigEndian32(body + size);
  for (std::uint32_t a = 0; a < attributes; ++a, at += sizeof(igtl_polydata_attribute_header)) {
    require(at + 1 < bytes.size() && bytes[at] == IGTL_POLY_ATTR_TYPE_SCALAR && bytes[at + 1] == 4,
            "OpenIGTLink POLYDATA: the colour attribute is not where the protocol puts it");
    bytes[at] = IGTL_POLY_ATTR_TYPE_RGBA;
  }
  std::uint64_t crc = crc64(bytes.data() + body, bytes.size() - body, 0);
  for (int i = 7; i >= 0; --i, crc >>= 8) bytes[IGTL_HEADER_SIZE - 8 + i] = static_cast<unsigned char>(crc & 0xff);
  return std::make_shared<const std::vector<unsigned char>>(std::move(bytes));
}

}  // namespace

PackedMessage packTransform(const std::string& name, const Eigen::Matrix4d& T, double timeS) {
  igtl::TransformMessage::Pointer message = igtl::TransformMessage::New();
  setHeader(message, name, timeS);
  igtl::Matrix4x4 matrix;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) matrix[r][c] = static_cast<float>(T(r, c));
  message->SetMatrix(matrix);
  return finish(message, "TRANSFORM", name);
}

std::vector<std::size_t> pointsWithinBudget(std::size_t modelPoints, std::size_t maxPoints) {
  const std::size_t count = std::min(modelPoints, maxPoints);
  std::vector<std::size_t> chosen(count);
  for (std::size_t i = 0; i < count; ++i) chosen[i] = count == modelPoints ? i : i * modelPoints / count;
  return chosen;
}

PackedMessage packPointCloud(const std::string& name, const ColoredPointCloud& cloud, std::size_t maxPoints,
                             double timeS) {
  require(maxPoints > 0, "the OpenIGTLink model's point budget must be positive");
  const std::vector<std::size_t> chosen = pointsWithinBudget(cloud.size(), maxPoints);
  igtl::PolyDataMessage::Pointer message = igtl::PolyDataMessage::New();
  setHeader(message, name, timeS);
  igtl::PolyDataPointArray::Pointer points = igtl::PolyDataPointArray::New();
  igtl::PolyDataCellArray::Pointer vertices = igtl::PolyDataCellArray::New();
  // AddPoint, not SetNumberOfPoints + SetPoint: 1.11's SetNumberOfPoints leaves the points without storage.
  for (std::size_t i = 0; i < chosen.size(); ++i) {
    const cv::Point3f& p = cloud.pointsMm[chosen[i]];
    points->AddPoint(p.x, p.y, p.z);
    igtlUint32 id = static_cast<igtlUint32>(i);
    vertices->AddCell(1, &id);
  }
  message->SetPoints(points);
  message->SetVertices(vertices);
  if (cloud.colorsRgb.size() == cloud.size() && !chosen.empty()) {
    std::vector<igtlFloat32> rgba(4 * chosen.size());
    for (std::size_t i = 0; i < chosen.size(); ++i) {
      const cv::Vec3b& c = cloud.colorsRgb[chosen[i]];
      for (int k = 0; k < 3; ++k) rgba[4 * i + k] = c[k] / 255.0f;
      rgba[4 * i + 3] = 1.0f;
    }
    igtl::PolyDataAttribute::Pointer colours = igtl::PolyDataAttribute::New();
    colours->SetType(igtl::PolyDataAttribute::POINT_SCALAR, 4);  // made POINT_RGBA after packing, see below
    colours->SetName(kColourAttributeName);
    colours->SetSize(static_cast<igtlUint32>(chosen.size()));
    colours->SetData(rgba.data());
    message->AddAttribute(colours);
  }
  PackedMessage packed = finish(message, "POLYDATA", name);
  if (message->GetNumberOfAttributes() > 0) packed.bytes = markAttributesRgba(*packed.bytes);
  return packed;
}

PackedMessage packStatus(const std::string& name, int code, const std::string& errorName, const std::string& text,
                         double timeS) {
  igtl::StatusMessage::Pointer message = igtl::StatusMessage::New();
  setHeader(message, name, timeS);
  message->SetCode(code);
  message->SetSubCode(0);
  message->SetErrorName(errorName.substr(0, 19).c_str());  // 20 bytes with the terminating zero
  message->SetStatusString(text.c_str());
  return finish(message, "STATUS", name);
}

PackedMessage packImage(const std::string& name, const cv::Mat& image, double timeS) {
  require(!image.empty() && image.depth() == CV_8U && (image.channels() == 1 || image.channels() == 3),
          "an OpenIGTLink IMAGE needs an 8-bit grey or BGR frame");
  cv::Mat pixels;
  if (image.channels() == 3) cv::cvtColor(image, pixels, cv::COLOR_BGR2RGB);
  else pixels = image.isContinuous() ? image : image.clone();
  igtl::ImageMessage::Pointer message = igtl::ImageMessage::New();
  setHeader(message, name, timeS);
  message->SetDimensions(pixels.cols, pixels.rows, 1);
  message->SetSpacing(1.0f, 1.0f, 1.0f);
  // Rows down -A: the frame stands upright in Slicer's axial (red) view, its top row at the largest A.
  float across[3] = {1, 0, 0}, down[3] = {0, -1, 0}, normal[3] = {0, 0, -1};
  message->SetNormals(across, down, normal);
  message->SetScalarTypeToUint8();
  message->SetNumComponents(pixels.channels());
  message->AllocateScalars();
  std::memcpy(message->GetScalarPointer(), pixels.data, pixels.total() * pixels.elemSize());
  return finish(message, "IMAGE", name);
}

}  // namespace tissuemosaic::igtlink
