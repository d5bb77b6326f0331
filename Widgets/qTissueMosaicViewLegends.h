#pragma once
/// @class qTissueMosaicViewLegends
/// @brief What a 3D view needs so that a surgeon can read it: orientation axes in the lower left corner (x red, y
/// green, z blue, in the view's world frame) and a scale bar at the bottom, "10 mm", measured in the plane of the
/// camera's focal point and kept at a round length (1, 2 or 5 times a power of ten) as the camera zooms. Both 3D
/// views of the application use it.
#include <vtkSmartPointer.h>

#include <string>

class vtkActor2D;
class vtkCallbackCommand;
class vtkObject;
class vtkOrientationMarkerWidget;
class vtkPoints;
class vtkRenderWindowInteractor;
class vtkRenderer;
class vtkTextActor;

class qTissueMosaicViewLegends {
public:
  /// Adds the scale bar to `renderer` and the axes to the interactor's window.
  qTissueMosaicViewLegends(vtkRenderer* renderer, vtkRenderWindowInteractor* interactor);
  ~qTissueMosaicViewLegends();
  qTissueMosaicViewLegends(const qTissueMosaicViewLegends&) = delete;
  qTissueMosaicViewLegends& operator=(const qTissueMosaicViewLegends&) = delete;

  /// The scale bar's length as of the last render (mm; 0 before) and its label ("10 mm").
  double scaleBarLengthMm() const { return this->BarLengthMm; }
  std::string scaleBarLabel() const;
  vtkOrientationMarkerWidget* axes() const;

private:
  static void onRender(vtkObject* caller, unsigned long event, void* clientData, void* callData);
  void updateScaleBar();

  vtkRenderer* Renderer;
  vtkSmartPointer<vtkActor2D> Bar;
  vtkSmartPointer<vtkPoints> BarPoints;
  vtkSmartPointer<vtkTextActor> Label;
  vtkSmartPointer<vtkOrientationMarkerWidget> Axes;
  vtkSmartPointer<vtkCallbackCommand> RenderCallback;
  unsigned long RenderObserver = 0;
  double BarLengthMm = 0;
};
