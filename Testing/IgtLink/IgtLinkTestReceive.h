#pragma once
/// @file IgtLinkTestReceive.h
/// @brief Test helper: receives one OpenIGTLink message with the library's own classes, its body's CRC checked.
/// Debian's OpenIGTLink 1.11 unpacks POINT_RGBA attributes as 9-component tensors (reading past the body): a
/// POLYDATA's RGBA attributes are counted in rgbaAttributes and handed to the library's unpacker as what they are
/// on the wire, 4-component float attributes, so that the points, cells and colours can be read back.
#include <igtlImageMessage.h>
#include <igtlMessageHeader.h>
#include <igtlPolyDataMessage.h>
#include <igtlSocket.h>
#include <igtlStatusMessage.h>
#include <igtlTimeStamp.h>
#include <igtlTransformMessage.h>
#include <igtl_header.h>
#include <igtl_polydata.h>
#include <igtl_util.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace tissuemosaic::igtlink::testing {

struct ReceivedMessage {
  std::string type, name;
  double timeS = 0;
  bool crcOk = false;
  igtl::MessageBase::Pointer message;  ///< TransformMessage, PolyDataMessage, StatusMessage or ImageMessage
  int rgbaAttributes = 0;              ///< POLYDATA: attributes sent as POINT_RGBA
};

inline std::uint64_t bigEndian(const unsigned char* bytes, int count) {
  std::uint64_t value = 0;
  for (int i = 0; i < count; ++i) value = value << 8 | bytes[i];
  return value;
}

/// False when the connection closed (or broke) before a whole message came.
inline bool receiveMessage(igtl::Socket* socket, ReceivedMessage& out) {
  igtl::MessageHeader::Pointer header = igtl::MessageHeader::New();
  header->InitPack();
  if (socket->Receive(header->GetPackPointer(), header->GetPackSize()) != header->GetPackSize()) return false;
  const std::uint64_t sentCrc = bigEndian(static_cast<unsigned char*>(header->GetPackPointer()) + IGTL_HEADER_SIZE - 8, 8);
  header->Unpack();
  out = ReceivedMessage{header->GetDeviceType(), header->GetDeviceName()};
  igtl::TimeStamp::Pointer stamp = igtl::TimeStamp::New();
  header->GetTimeStamp(stamp);
  out.timeS = stamp->GetTimeStamp();
  if (out.type == "TRANSFORM") out.message = igtl::TransformMessage::New().GetPointer();
  else if (out.type == "POLYDATA") out.message = igtl::PolyDataMessage::New().GetPointer();
  else if (out.type == "STATUS") out.message = igtl::StatusMessage::New().GetPointer();
  else if (out.type == "IMAGE") out.message = igtl::ImageMessage::New().GetPointer();
  if (!out.message) {  // another type: skipped
    return socket->Skip(header->GetBodySizeToRead(), 1) == header->GetBodySizeToRead();
  }
  out.message->SetMessageHeader(header);
  out.message->AllocatePack();
  auto* body = static_cast<unsigned char*>(out.message->GetPackBodyPointer());
  const int bodySize = out.message->GetPackBodySize();
  if (socket->Receive(body, bodySize) != bodySize) return false;
  if (out.type != "POLYDATA") {
    out.crcOk = (out.message->Unpack(1) & igtl::MessageHeader::UNPACK_BODY) != 0;
    return true;
  }
  out.crcOk = crc64(body, static_cast<igtl_uint64>(bodySize), 0) == sentCrc;
  if (!out.crcOk || bodySize < static_cast<int>(sizeof(igtl_polydata_header))) return true;
  const std::uint64_t points = bigEndian(body, 4), attributes = bigEndian(body + 36, 4);
  std::size_t at = sizeof(igtl_polydata_header) + 12 * points;
  for (int field : {8, 16, 24, 32}) at += bigEndian(body + field, 4);
  for (std::uint64_t a = 0; a < attributes && at + 1 < static_cast<std::size_t>(bodySize);
       ++a, at += sizeof(igtl_polydata_attribute_header)) {
    if (body[at] == IGTL_POLY_ATTR_TYPE_RGBA && body[at + 1] == 4) {
      body[at] = IGTL_POLY_ATTR_TYPE_SCALAR;
      ++out.rgbaAttributes;
    }
  }
  out.message->Unpack(0);  // the CRC was checked above, on the body as sent
  return true;
}

}  // namespace tissuemosaic::igtlink::testing
