#include "vtkTissueMosaicVtkMessages.h"

#include <vtkAlgorithm.h>
#include <vtkCommand.h>
#include <vtkExecutive.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>

namespace tissuemosaic {

/// Forwards what VTK objects without observers print (e.g. vtkXMLDataParser) to the catcher.
class CapturingOutputWindow : public vtkOutputWindow {
public:
  static CapturingOutputWindow* New();
  vtkTypeMacro(CapturingOutputWindow, vtkOutputWindow);
  void DisplayErrorText(const char* text) override { catcher->add(true, text); }
  void DisplayWarningText(const char* text) override { catcher->add(false, text); }
  void DisplayGenericWarningText(const char* text) override { catcher->add(false, text); }
  VtkMessageCatcher* catcher = nullptr;
};
vtkStandardNewMacro(CapturingOutputWindow);

VtkMessageCatcher::VtkMessageCatcher(vtkAlgorithm* algorithm) : algorithm_(algorithm) {
  callback_->SetClientData(this);
  callback_->SetCallback(&VtkMessageCatcher::onMessage);
  for (vtkObject* object : {static_cast<vtkObject*>(algorithm_), static_cast<vtkObject*>(algorithm_->GetExecutive())}) {
    object->AddObserver(vtkCommand::ErrorEvent, callback_);
    object->AddObserver(vtkCommand::WarningEvent, callback_);
  }
  // SetInstance releases the window it replaces: keep our own reference to put it back.
  previousWindow_ = vtkOutputWindow::GetInstance();
  previousWindow_->Register(nullptr);
  vtkNew<CapturingOutputWindow> window;
  window->catcher = this;
  vtkOutputWindow::SetInstance(window);
}

VtkMessageCatcher::~VtkMessageCatcher() {
  vtkOutputWindow::SetInstance(previousWindow_);
  previousWindow_->UnRegister(nullptr);
  algorithm_->GetExecutive()->RemoveObserver(callback_);
  algorithm_->RemoveObserver(callback_);
}

void VtkMessageCatcher::add(bool error, const char* text) {
  if (error) ++errors_;
  std::string message = text ? text : "(no message)";
  // VTK prefixes "ERROR: In <source file>, line N": the user needs the message, not our build's paths.
  if (message.rfind("ERROR: In ", 0) == 0 || message.rfind("Warning: In ", 0) == 0) {
    const auto newline = message.find('\n');
    if (newline != std::string::npos) message.erase(0, newline + 1);
  }
  // The executive's "returned failure for request: vtkInformation (0x...)" is followed by the request's whole dump
  // (Debug, Modified Time, Reference Count, keys...): internals, not a reason. The reader's own error says why.
  const auto dump = message.find(" for request: vtkInformation");
  if (dump != std::string::npos) message.erase(dump);
  // "vtkSTLReader (0x55d...)": no object addresses.
  for (auto address = message.find("(0x"); address != std::string::npos; address = message.find("(0x", address)) {
    const auto close = message.find(')', address);
    if (close == std::string::npos) break;
    message.erase(address, close - address + 1);
  }
  while (!message.empty() && (message.back() == '\n' || message.back() == '\r' || message.back() == ' ')) {
    message.pop_back();
  }
  if (!messages_.empty()) messages_ += '\n';
  messages_ += message;
}

void VtkMessageCatcher::onMessage(vtkObject*, unsigned long event, void* clientData, void* callData) {
  static_cast<VtkMessageCatcher*>(clientData)->add(event == vtkCommand::ErrorEvent, static_cast<const char*>(callData));
}

}  // namespace tissuemosaic
