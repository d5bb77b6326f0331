#pragma once
/// @class vtkTissueMosaicModelScene
/// @brief The 3D scene of a reconstruction, the same in the desktop application's view and in offscreen
/// snapshots: the textured point model (its own colours, unlit), the key-frame camera frusta, the current camera
/// and the camera path; and a "scope view" camera placement (looking along the scope, image up on screen).
///
/// The inputs are the polydata objects the reconstruction logic updates in place; after an update the next
/// Render() of the render window draws the new data.
#include <vtkObject.h>
#include <vtkSmartPointer.h>

class vtkActor;
class vtkPolyData;
class vtkPolyDataMapper;
class vtkRenderer;

namespace tissuemosaic {
/// Every k-th point of `model` (k = ceil(points / maxPoints)) with its point data (colours, normals), one vertex
/// cell each, into `subsample`. Returns k.
vtkIdType subsampleModel(vtkPolyData* model, vtkIdType maxPoints, vtkPolyData* subsample);
}  // namespace tissuemosaic

class vtkTissueMosaicModelScene : public vtkObject {
public:
  static vtkTissueMosaicModelScene* New();
  vtkTypeMacro(vtkTissueMosaicModelScene, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkTissueMosaicModelScene(const vtkTissueMosaicModelScene&) = delete;
  void operator=(const vtkTissueMosaicModelScene&) = delete;

  /// @name Inputs (any may be null: that part is not drawn)
  ///@{
  void SetModel(vtkPolyData* model);
  void SetKeyFrameFrusta(vtkPolyData* frusta);
  void SetCurrentFrustum(vtkPolyData* frustum);
  void SetTrajectory(vtkPolyData* trajectory);
  ///@}

  /// Adds the actors (once per renderer) and sets its background.
  void AddToRenderer(vtkRenderer* renderer);

  /// Points are drawn as squares of this many pixels.
  void SetPointSizePx(double sizePx);
  /// Sets the point size so that the model, as the renderer's camera shows it now, looks closed: about the
  /// spacing of its points on screen (its projected bounding box shared among its points), 2 to 8 pixels. A
  /// scan seen at several times its video's resolution had shown the background through a grid of gaps.
  void FitPointSizeToView(vtkRenderer* renderer);
  double GetPointSizePx() const { return this->PointSizePx; }

  /// Places the camera behind the first left camera, looking along its optical axis (world +z forward, -y up:
  /// the engine's world frame is that camera), so that the model appears as the surgeon saw it, and fits the view
  /// to `fitTo`'s points (the model; the frusta, nearer the camera, would otherwise fill the picture), or to every
  /// visible actor when it is null or empty.
  static void ResetScopeView(vtkRenderer* renderer, vtkActor* fitTo = nullptr);

  /// @name Level of detail while the user turns the view
  /// A point model of millions of points can take longer than an interactive frame to draw (software OpenGL,
  /// small GPUs). While SetInteracting(true), and when the model has more points than the budget, the model
  /// actor draws an even subsample of at most InteractivePointBudget points instead (with larger points, so the
  /// surface still looks closed); SetInteracting(false) puts the full model back. Budget 0: always the full model.
  ///@{
  void SetInteractivePointBudget(vtkIdType points);
  vtkIdType GetInteractivePointBudget() const { return this->InteractivePointBudget; }
  void SetInteracting(bool interacting);
  bool GetInteracting() const { return this->Interacting; }
  /// Points the model actor draws now.
  vtkIdType GetDrawnModelPoints();
  ///@}

  vtkActor* GetModelActor() { return this->ModelActor; }
  vtkActor* GetKeyFrameFrustaActor() { return this->KeyFrameFrustaActor; }
  vtkActor* GetCurrentFrustumActor() { return this->CurrentFrustumActor; }
  vtkActor* GetTrajectoryActor() { return this->TrajectoryActor; }

protected:
  vtkTissueMosaicModelScene();
  ~vtkTissueMosaicModelScene() override;

private:
  vtkSmartPointer<vtkActor> ModelActor;
  vtkSmartPointer<vtkPolyDataMapper> FullMapper;
  vtkSmartPointer<vtkPolyDataMapper> InteractiveMapper;
  vtkSmartPointer<vtkPolyData> InteractiveModel;  ///< the subsample
  vtkMTimeType InteractiveModelTime = 0;          ///< the model's MTime when the subsample was made
  vtkIdType InteractivePointBudget = 0;
  bool Interacting = false;
  double PointSizePx = 2.0;
  vtkSmartPointer<vtkActor> KeyFrameFrustaActor;
  vtkSmartPointer<vtkActor> CurrentFrustumActor;
  vtkSmartPointer<vtkActor> TrajectoryActor;
};
