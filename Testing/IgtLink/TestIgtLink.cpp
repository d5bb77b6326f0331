// The OpenIGTLink link: messages as a client written against the library's own classes receives them (CRC checked),
// the publisher's rules, a server that a silent, slow or leaving client cannot hold up, and video input from a server
// (two IMAGE streams paired by time stamp, or one side-by-side stream).
#include "Core/Error.h"
#include "IgtLinkPublisher.h"
#include "IgtLinkServer.h"
#include "IgtLinkTestReceive.h"
#include "IgtLinkVideoSource.h"

#include <gtest/gtest.h>
#include <igtlClientSocket.h>
#include <igtlImageMessage.h>
#include <igtlMessageHeader.h>
#include <igtlPolyDataMessage.h>
#include <igtlStatusMessage.h>
#include <igtlTransformMessage.h>
#include <opencv2/imgproc.hpp>

#include <chrono>
#include <future>
#include <thread>

namespace tissuemosaic::igtlink {
namespace {

using Clock = std::chrono::steady_clock;

igtl::ClientSocket::Pointer connectTo(const IgtLinkServer& server) {
  igtl::ClientSocket::Pointer socket = igtl::ClientSocket::New();
  EXPECT_EQ(socket->ConnectToServer("localhost", server.port()), 0);
  socket->SetReceiveTimeout(10000);  // a test that fails does not hang
  EXPECT_TRUE(server.waitForClient(5.0));
  return socket;
}

/// The next message, its CRC checked (empty type when the connection closed).
struct Message {
  std::string type, name;
  igtl::MessageBase::Pointer body;
  int rgbaAttributes = 0;
};
Message receive(igtl::ClientSocket* socket) {
  testing::ReceivedMessage received;
  if (!testing::receiveMessage(socket, received)) return {};
  EXPECT_TRUE(received.crcOk) << "CRC check failed: " << received.type;
  return {received.type, received.name, received.message, received.rgbaAttributes};
}

Eigen::Matrix4d pose(double angleRad, double xMm) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.block<2, 2>(0, 0) << std::cos(angleRad), -std::sin(angleRad), std::sin(angleRad), std::cos(angleRad);
  T(0, 3) = xMm;
  T(1, 3) = -12.25;
  T(2, 3) = 80.5;
  return T;
}

TEST(IgtLink, PublisherSendsTransformsPerTrackedFrameAndStatusOnLossAndRelocalisation) {
  IgtLinkServer server(0);
  igtl::ClientSocket::Pointer client = connectTo(server);
  IgtLinkPublisher publisher(server, {});
  publisher.frameProcessed(0, 0.0, true, pose(0.1, 1.5), "", {});
  publisher.frameProcessed(1, 1 / 30.0, true, pose(0.2, 2.5), "", {});
  publisher.frameProcessed(2, 2 / 30.0, false, {}, "too few matches", {});
  publisher.frameProcessed(3, 3 / 30.0, false, {}, "too few matches", {});
  publisher.frameProcessed(4, 4 / 30.0, true, pose(0.3, 3.5), "", {});

  const std::vector<std::string> expected = {"TRANSFORM", "TRANSFORM", "STATUS", "STATUS", "TRANSFORM"};
  int transforms = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const Message m = receive(client);
    ASSERT_EQ(m.type, expected[i]) << i;
    if (m.type == "TRANSFORM") {
      EXPECT_EQ(m.name, "LeftCameraToModel");
      auto* transform = static_cast<igtl::TransformMessage*>(m.body.GetPointer());
      igtl::Matrix4x4 matrix;
      transform->GetMatrix(matrix);
      const Eigen::Matrix4d sent = pose(0.1 * (transforms + 1), 1.5 + transforms);
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) EXPECT_NEAR(matrix[r][c], sent(r, c), 1e-5) << r << c;
      igtl::TimeStamp::Pointer stamp = igtl::TimeStamp::New();
      transform->GetTimeStamp(stamp);
      EXPECT_NEAR(stamp->GetTimeStamp(), (transforms == 2 ? 4 : transforms) / 30.0, 1e-8);
      ++transforms;
    } else {
      auto* status = static_cast<igtl::StatusMessage*>(m.body.GetPointer());
      EXPECT_EQ(m.name, "TissueMosaic");
      EXPECT_EQ(std::string(status->GetErrorName()), i == 2 ? "Lost" : "Relocalised");
      EXPECT_EQ(status->GetCode(), i == 2 ? igtl::StatusMessage::STATUS_NOT_FOUND : igtl::StatusMessage::STATUS_OK);
      if (i == 2) EXPECT_NE(std::string(status->GetStatusString()).find("too few matches"), std::string::npos);
    }
  }
}

ColoredPointCloud testCloud(std::size_t points) {
  ColoredPointCloud cloud;
  for (std::size_t i = 0; i < points; ++i) {
    cloud.pointsMm.emplace_back(static_cast<float>(i), 0.5f * i, 60.0f);
    cloud.colorsRgb.emplace_back(static_cast<uchar>(i % 256), 255, 0);
  }
  return cloud;
}

TEST(IgtLink, ModelWithinThePointBudgetWithColoursInZeroToOne) {
  EXPECT_EQ(pointsWithinBudget(10, 20).size(), 10u);
  const std::vector<std::size_t> spread = pointsWithinBudget(1000, 300);
  ASSERT_EQ(spread.size(), 300u);
  EXPECT_EQ(spread.front(), 0u);
  EXPECT_GT(spread.back(), 990u);  // spread over the whole model, not its first 300 points
  IgtLinkServer server(0);
  igtl::ClientSocket::Pointer client = connectTo(server);
  for (std::size_t budget : {std::size_t(300), std::size_t(5000)}) {
    server.send(packPointCloud(kModelName, testCloud(1000), budget, 2.0), true);
    const Message m = receive(client);
    ASSERT_EQ(m.type, "POLYDATA");
    EXPECT_EQ(m.name, "TissueModel");
    auto* polydata = static_cast<igtl::PolyDataMessage*>(m.body.GetPointer());
    const int points = polydata->GetPoints()->GetNumberOfPoints();
    EXPECT_EQ(points, static_cast<int>(std::min<std::size_t>(budget, 1000)));
    EXPECT_EQ(static_cast<int>(polydata->GetVertices()->GetNumberOfCells()), points);
    ASSERT_EQ(polydata->GetNumberOfAttributes(), 1);
    EXPECT_EQ(m.rgbaAttributes, 1) << "the colours travel as POINT_RGBA";
    igtl::PolyDataAttribute* colours = polydata->GetAttribute(0);
    EXPECT_EQ(std::string(colours->GetName()), "Colors");
    EXPECT_EQ(colours->GetNumberOfComponents(), 4u);
    std::vector<igtlFloat32> rgba(4 * points);
    colours->GetData(rgba.data());
    const std::vector<std::size_t> chosen = pointsWithinBudget(1000, budget);
    for (int i = 0; i < points; i += 37) {
      igtlFloat32 xyz[3];
      polydata->GetPoints()->GetPoint(i, xyz);
      EXPECT_EQ(xyz[0], static_cast<float>(chosen[i]));
      EXPECT_FLOAT_EQ(rgba[4 * i], (chosen[i] % 256) / 255.0f);
      EXPECT_EQ(rgba[4 * i + 1], 1.0f);
      EXPECT_EQ(rgba[4 * i + 3], 1.0f);
    }
  }
}

TEST(IgtLink, PublisherRateLimitsModelsAndSendsTheFinalOneBeforeFinished) {
  IgtLinkServer server(0);
  IgtLinkPublisherOptions options;
  options.maxModelRateHz = 2.0;
  IgtLinkPublisher publisher(server, options);
  EXPECT_FALSE(publisher.modelDue());  // nobody to send to: no snapshot needed
  igtl::ClientSocket::Pointer client = connectTo(server);
  EXPECT_TRUE(publisher.modelDue());
  publisher.modelUpdated(testCloud(100), 1.0);
  EXPECT_FALSE(publisher.modelDue());  // within 0.5 s of the last one
  std::this_thread::sleep_for(std::chrono::milliseconds(550));
  EXPECT_TRUE(publisher.modelDue());
  publisher.finished(testCloud(250), 9.0, "done");
  std::vector<std::string> order;
  int lastPoints = 0;
  for (int i = 0; i < 3; ++i) {
    const Message m = receive(client);
    order.push_back(m.type);
    if (m.type == "POLYDATA")
      lastPoints = static_cast<igtl::PolyDataMessage*>(m.body.GetPointer())->GetPoints()->GetNumberOfPoints();
  }
  EXPECT_EQ(order, (std::vector<std::string>{"POLYDATA", "POLYDATA", "STATUS"}));
  EXPECT_EQ(lastPoints, 250);
}

TEST(IgtLink, SilentSlowAndLeavingClientsNeverHoldUpTheSender) {
  IgtLinkServer::Options options;
  options.sendTimeoutMs = 300;
  IgtLinkServer server(0, options);
  igtl::ClientSocket::Pointer silent = connectTo(server);  // connects and never reads
  igtl::ClientSocket::Pointer leaving = igtl::ClientSocket::New();
  ASSERT_EQ(leaving->ConnectToServer("localhost", server.port()), 0);
  igtl::ClientSocket::Pointer good = igtl::ClientSocket::New();
  ASSERT_EQ(good->ConnectToServer("localhost", server.port()), 0);
  good->SetReceiveTimeout(10000);
  const auto connected = Clock::now() + std::chrono::seconds(5);
  while (server.clientCount() < 3 && Clock::now() < connected) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_EQ(server.clientCount(), 3);
  leaving->CloseSocket();

  // 40 models of 2 MB each and 300 transforms: far more than the silent client's socket buffers hold.
  const PackedMessage model = packPointCloud(kModelName, testCloud(70000), 500000, 0.0);
  ASSERT_GT(model.size(), 2000000u);
  std::future<int> goodReader = std::async(std::launch::async, [&] {
    int transforms = 0;
    for (;;) {
      const Message m = receive(good);
      if (m.type.empty() || (m.type == "STATUS")) return transforms;
      transforms += m.type == "TRANSFORM";
    }
  });
  double slowestSendMs = 0;
  // Over 1.5 s: time for the silent client's socket buffers to fill and its sender to time out.
  for (int i = 0; i < 300; ++i) {
    const auto start = Clock::now();
    if (i % 4 == 0) server.send(model, true);
    server.send(packTransform(kCameraTransformName, pose(0, i), i / 30.0), false);
    slowestSendMs = std::max(slowestSendMs, std::chrono::duration<double, std::milli>(Clock::now() - start).count());
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_LT(slowestSendMs, 100.0) << "send() must only queue";
  EXPECT_TRUE(server.flush(10.0)) << "the silent client is dropped after its send timeout";
  server.send(packStatus(kStatusName, 1, "Finished", "end", 10.0), false);
  EXPECT_EQ(goodReader.get(), 300) << "the good client got every transform, in spite of the others";
  const auto dropped = Clock::now() + std::chrono::seconds(5);
  while ((server.clientCount() > 1 || server.counters().disconnections < 2) && Clock::now() < dropped)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(server.clientCount(), 1);
  EXPECT_GE(server.counters().disconnections, 2);
  EXPECT_GT(server.counters().messagesDropped, 0) << "models the silent client never took were replaced";

  // A client that comes back gets the messages from then on.
  igtl::ClientSocket::Pointer back = igtl::ClientSocket::New();
  ASSERT_EQ(back->ConnectToServer("localhost", server.port()), 0);
  back->SetReceiveTimeout(10000);
  const auto reconnected = Clock::now() + std::chrono::seconds(5);
  while (server.clientCount() < 2 && Clock::now() < reconnected) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  server.send(packTransform(kCameraTransformName, pose(0, 1), 11.0), false);
  EXPECT_EQ(receive(back).type, "TRANSFORM");
  silent->CloseSocket();
}

TEST(IgtLink, PortInUseIsAClearError) {
  IgtLinkServer first(0);
  try {
    IgtLinkServer second(first.port());
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("port " + std::to_string(first.port())), std::string::npos) << e.what();
  }
}

TEST(IgtLink, ThePortIsFreeAgainAsSoonAsAServerWithClientsEnds) {
  // The server closes its clients' connections first, which leaves them in TCP's TIME_WAIT for a minute: the next
  // scan on the same port must start at once all the same.
  int port = 0;
  igtl::ClientSocket::Pointer client;  // outlives the server, which closes the connection first
  {
    IgtLinkServer first(0);
    port = first.port();
    client = connectTo(first);
    first.send(packTransform(kCameraTransformName, pose(0, 1), 11.0), false);
    EXPECT_EQ(receive(client).type, "TRANSFORM");
  }
  EXPECT_NO_THROW(IgtLinkServer again(port));
}

cv::Mat eye(int index, bool right) {
  cv::Mat image(48, 64, CV_8UC3, cv::Scalar(10 + index, right ? 200 : 50, 90));
  cv::circle(image, cv::Point(right ? 20 : 40, 24), 8, cv::Scalar(255, 255, 255), -1);
  return image;
}

TEST(IgtLinkVideoSource, PairsTwoImageStreamsByTimeStampAndSkipsOtherMessages) {
  IgtLinkServer server(0);
  IgtLinkVideoInput input;
  input.port = server.port();
  input.leftName = "LeftImage";
  input.rightName = "RightImage";
  std::future<std::unique_ptr<StereoFrameSource>> opening =
      std::async(std::launch::async, [&] { return openIgtLinkVideo(input); });
  ASSERT_TRUE(server.waitForClient(10.0));
  // PLUS sends STATUS keep-alives and transforms too; the right eye's stamps differ by 1 ms; frame 2's right eye
  // never comes.
  server.send(packStatus("Keepalive", 1, "OK", "", 0.0), false);
  for (int i = 0; i < 5; ++i) {
    server.send(packImage("LeftImage", eye(i, false), 1.0 + i / 30.0), false);
    server.send(packTransform("ProbeToReference", pose(0, i), 1.0 + i / 30.0), false);
    if (i != 2) server.send(packImage("RightImage", eye(i, true), 1.001 + i / 30.0), false);
  }
  std::unique_ptr<StereoFrameSource> source = opening.get();
  EXPECT_TRUE(source->isLive());
  EXPECT_EQ(source->frameSize(), cv::Size(64, 48));
  ASSERT_TRUE(server.flush(5.0));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // let the source receive everything
  StereoFrame frame;
  ASSERT_TRUE(source->next(frame));  // the newest pair: frame 4
  EXPECT_NEAR(frame.timeS, 1.0 + 4 / 30.0, 1e-6);
  EXPECT_EQ(cv::norm(frame.left, eye(4, false), cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(frame.right, eye(4, true), cv::NORM_INF), 0.0);
  EXPECT_EQ(source->droppedFrames(), 4) << "frames 0-3 were replaced by newer ones before next() took them";
  server.send(packImage("RightImage", eye(5, true), 1.001 + 5 / 30.0), false);
  server.send(packImage("LeftImage", eye(5, false), 1.0 + 5 / 30.0), false);
  ASSERT_TRUE(source->next(frame));
  EXPECT_EQ(cv::norm(frame.left, eye(5, false), cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(frame.right, eye(5, true), cv::NORM_INF), 0.0);
  source->interrupt();
  EXPECT_FALSE(source->next(frame));
}

TEST(IgtLinkVideoSource, OnePackedStreamInAnyLayout) {
  IgtLinkServer server(0);
  IgtLinkVideoInput input;
  input.port = server.port();
  input.packedName = "Video";
  input.layout = VideoLayout::TopBottom;
  std::future<std::unique_ptr<StereoFrameSource>> opening =
      std::async(std::launch::async, [&] { return openIgtLinkVideo(input); });
  ASSERT_TRUE(server.waitForClient(10.0));
  server.send(packImage("Video", packStereoFrame(eye(7, false), eye(7, true), VideoLayout::TopBottom), 3.0), false);
  std::unique_ptr<StereoFrameSource> source = opening.get();
  StereoFrame frame;
  ASSERT_TRUE(source->next(frame));
  EXPECT_EQ(cv::norm(frame.left, eye(7, false), cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(frame.right, eye(7, true), cv::NORM_INF), 0.0);
}

TEST(IgtLinkVideoSource, NoServerIsAClearError) {
  IgtLinkVideoInput input;
  input.port = 1;  // nothing listens there
  input.packedName = "Video";
  input.connectTimeoutS = 0.3;
  EXPECT_THROW(openIgtLinkVideo(input), Error);
  std::string host;
  int port = 0;
  IgtLinkVideoInput::parseAddress("plus.local:18945", host, port);
  EXPECT_EQ(host, "plus.local");
  EXPECT_EQ(port, 18945);
  EXPECT_THROW(IgtLinkVideoInput::parseAddress("plus.local:", host, port), Error);
}

}  // namespace
}  // namespace tissuemosaic::igtlink
