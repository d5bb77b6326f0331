#pragma once
/// @file vtkTissueMosaicVtkMessages.h
/// @brief Collects the errors and warnings a VTK reader or writer (its executive and helper objects, such as the
/// XML parser) reports, so that a bad file becomes one tissuemosaic::Error with VTK's own words instead of text on
/// the console. While a catcher lives, it also replaces the global vtkOutputWindow (restored afterwards): use
/// it around one read or write on one thread.
#include <vtkCallbackCommand.h>
#include <vtkNew.h>

#include <string>

class vtkAlgorithm;
class vtkOutputWindow;

namespace tissuemosaic {

class VtkMessageCatcher {
public:
  /// Observes ErrorEvent and WarningEvent of the algorithm and of its executive until destroyed.
  explicit VtkMessageCatcher(vtkAlgorithm* algorithm);
  ~VtkMessageCatcher();
  VtkMessageCatcher(const VtkMessageCatcher&) = delete;
  VtkMessageCatcher& operator=(const VtkMessageCatcher&) = delete;

  bool hasErrors() const { return errors_ > 0; }
  /// Every message caught, one per line.
  const std::string& messages() const { return messages_; }

private:
  static void onMessage(vtkObject* caller, unsigned long event, void* clientData, void* callData);
  friend class CapturingOutputWindow;
  void add(bool error, const char* text);

  vtkAlgorithm* algorithm_;
  vtkOutputWindow* previousWindow_ = nullptr;
  vtkNew<vtkCallbackCommand> callback_;
  std::string messages_;
  int errors_ = 0;
};

}  // namespace tissuemosaic
