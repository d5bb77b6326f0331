// The OpenIGTLink panel (issue 31): port, on/off, clients connected; with its observer on the reconstruction logic,
// a scan run in the app streams one TRANSFORM per tracked frame, the model and STATUS Finished to a client built on
// the OpenIGTLink classes (CRC checked). Qt's offscreen platform.
#include "qTissueMosaicIgtLinkWidget.h"
#include "vtkTissueMosaicReconstructionLogic.h"

#include "IgtLinkTestReceive.h"
#include "SyntheticScanFrameSource.h"

#include <gtest/gtest.h>
#include <igtlClientSocket.h>
#include <igtlMessageHeader.h>
#include <igtlPolyDataMessage.h>
#include <igtlStatusMessage.h>
#include <igtlTransformMessage.h>

#include <vtkNew.h>

#include <QApplication>
#include <QCheckBox>
#include <QLabel>
#include <QLineEdit>
#include <QSpinBox>

#include <chrono>
#include <future>
#include <thread>

namespace {

void processEventsFor(int ms) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
  while (std::chrono::steady_clock::now() < end) {
    QApplication::processEvents();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

TEST(IgtLinkWidget, ServerOnOffClientsAndAScanStreamedToAClient) {
  qTissueMosaicIgtLinkWidget panel;
  EXPECT_EQ(panel.findChild<QSpinBox*>("igtlPortSpinBox")->value(), 18944);
  EXPECT_EQ(panel.findChild<QLineEdit*>("igtlBindLineEdit")->text(), "127.0.0.1") << "loopback unless told otherwise";
  panel.setPort(0);  // any free port: tests run side by side
  ASSERT_TRUE(panel.setServerOn(true));
  EXPECT_TRUE(panel.findChild<QCheckBox*>("igtlServerCheckBox")->isChecked());
  EXPECT_FALSE(panel.findChild<QSpinBox*>("igtlPortSpinBox")->isEnabled()) << "the port is fixed while on";
  const int port = panel.port();
  ASSERT_GT(port, 0);

  igtl::ClientSocket::Pointer client = igtl::ClientSocket::New();
  ASSERT_EQ(client->ConnectToServer("localhost", port), 0);
  processEventsFor(700);
  EXPECT_EQ(panel.clientCount(), 1);
  EXPECT_TRUE(panel.findChild<QLabel*>("igtlClientsLabel")->text().contains("1 client(s) connected"))
      << panel.findChild<QLabel*>("igtlClientsLabel")->text().toStdString();
  EXPECT_TRUE(panel.findChild<QLabel*>("igtlClientsLabel")->text().contains("listening on 127.0.0.1 port"));
  EXPECT_FALSE(panel.findChild<QLineEdit*>("igtlBindLineEdit")->isEnabled()) << "the address is fixed while on";

  // The client reads everything until STATUS Finished, in the background.
  std::future<std::tuple<int, int, std::string>> reading = std::async(std::launch::async, [&] {
    int transforms = 0, lastModelPoints = -1;
    tissuemosaic::igtlink::testing::ReceivedMessage m;
    while (tissuemosaic::igtlink::testing::receiveMessage(client, m)) {
      if (!m.crcOk) return std::tuple<int, int, std::string>{-1, -1, "CRC"};
      if (m.type == "TRANSFORM") ++transforms;
      if (m.type == "POLYDATA")
        lastModelPoints = static_cast<igtl::PolyDataMessage*>(m.message.GetPointer())->GetPoints()->GetNumberOfPoints();
      if (m.type == "STATUS" &&
          std::string(static_cast<igtl::StatusMessage*>(m.message.GetPointer())->GetErrorName()) == "Finished")
        return std::tuple<int, int, std::string>{transforms, lastModelPoints, "Finished"};
    }
    return std::tuple<int, int, std::string>{transforms, lastModelPoints, "closed"};
  });

  auto scan = std::make_shared<const tissuemosaic::synthetic::SyntheticScan>(tissuemosaic::testing::shortScanOptions(12));
  vtkNew<vtkTissueMosaicReconstructionLogic> logic;
  logic->SetScanObserver(panel.scanObserver());
  logic->SetDeviceChoice(vtkTissueMosaicReconstructionLogic::DeviceCpu);
  ASSERT_TRUE(logic->SetFrameSourceFactory(
      [scan] { return std::make_unique<tissuemosaic::testing::SyntheticScanFrameSource>(scan); }));
  logic->SetRectifiedGeometry(scan->geometry());
  ASSERT_TRUE(logic->Start()) << logic->GetLastErrorText();
  ASSERT_TRUE(logic->WaitForScanEnd(300.0));
  logic->UpdateOutputs();
  const auto [transforms, modelPoints, last] = reading.get();
  EXPECT_EQ(last, "Finished");
  EXPECT_EQ(transforms, logic->GetStatus().framesProcessed - logic->GetStatus().lostFrames);
  EXPECT_EQ(modelPoints, logic->GetStatus().modelPoints) << "the final model, whole (under the budget)";

  ASSERT_TRUE(panel.setServerOn(false));
  EXPECT_FALSE(panel.isServerOn());
  processEventsFor(100);
  EXPECT_EQ(panel.findChild<QLabel*>("igtlClientsLabel")->text(), "off");
}

}  // namespace
