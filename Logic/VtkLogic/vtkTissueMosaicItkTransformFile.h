#pragma once
/// @file vtkTissueMosaicItkTransformFile.h
/// @brief Linear transforms as ITK text transform files (.tfm, "#Insight Transform File V1.0"), which 3D Slicer
/// loads as a linear transform node.
///
/// Direction: an ITK transform maps points of the FIXED space to the MOVING space (the resampling convention).
/// Slicer therefore inverts a loaded .tfm to get its "transform to parent". To move the model onto the CT in
/// Slicer (model node under the loaded transform), the file must hold the inverse of T_target_model, i.e.
/// T_model_target: writeModelToTargetTransform does that. All coordinates are LPS millimetres, as in ITK.
#include <Eigen/Core>

#include <string>

namespace tissuemosaic {

/// Writes an affine 4x4 (last row 0 0 0 1) as AffineTransform_double_3_3: 12 parameters (the 3x3 matrix row by
/// row, then the translation) and FixedParameters 0 0 0 (the centre). Throws Error when writing fails.
void writeItkTransformFile(const std::string& path, const Eigen::Matrix4d& itkFixedToMovingLps);

/// Reads the first transform of a .tfm file: a *_double_3_3 / *_float_3_3 linear transform stored as 12
/// parameters (AffineTransform_, MatrixOffsetTransformBase_, ...) or a 3-parameter TranslationTransform_,
/// applying the FixedParameters centre as ITK does (y = A (x - c) + t + c). Throws Error for other content.
Eigen::Matrix4d readItkTransformFile(const std::string& path);

/// Writes T_target_model (model -> CT, LPS) for Slicer: the file holds its inverse.
void writeModelToTargetTransform(const std::string& path, const Eigen::Matrix4d& targetFromModelLps);

/// Reads a file written by writeModelToTargetTransform (or saved by Slicer for a model->CT transform node) back
/// as T_target_model.
Eigen::Matrix4d readModelToTargetTransform(const std::string& path);

}  // namespace tissuemosaic
