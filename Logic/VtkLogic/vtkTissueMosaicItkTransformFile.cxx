#include "vtkTissueMosaicItkTransformFile.h"

#include "IO/AtomicFile.h"
#include "Core/Error.h"

#include <Eigen/Dense>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <vector>

namespace tissuemosaic {

namespace {

std::string trimmed(const std::string& text) {
  const auto begin = text.find_first_not_of(" \t\r\n");
  if (begin == std::string::npos) return "";
  return text.substr(begin, text.find_last_not_of(" \t\r\n") - begin + 1);
}

std::vector<double> numbers(const std::string& text, const std::string& path, const std::string& key) {
  std::istringstream in(text);
  std::vector<double> values;
  std::string word;
  while (in >> word) {
    try {
      std::size_t used = 0;
      values.push_back(std::stod(word, &used));
      if (used != word.size()) throw std::invalid_argument(word);
    } catch (const std::exception&) {
      throw Error("transform file '" + path + "': '" + key + "' holds '" + word + "', not a number");
    }
  }
  return values;
}

bool isAffine(const Eigen::Matrix4d& matrix) {
  return matrix.allFinite() && matrix.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1), 1e-12);
}

}  // namespace

void writeItkTransformFile(const std::string& path, const Eigen::Matrix4d& itkFixedToMovingLps) {
  require(isAffine(itkFixedToMovingLps), "cannot write '" + path + "': the transform is not a finite affine 4x4");
  writeStreamAtomically(path, "transform file", [&](std::ostream& file) {
    file << std::setprecision(17);
    file << "#Insight Transform File V1.0\n#Transform 0\nTransform: AffineTransform_double_3_3\nParameters:";
    for (int row = 0; row < 3; ++row) {
      for (int col = 0; col < 3; ++col) file << ' ' << itkFixedToMovingLps(row, col);
    }
    for (int row = 0; row < 3; ++row) file << ' ' << itkFixedToMovingLps(row, 3);
    file << "\nFixedParameters: 0 0 0\n";
  });
}

Eigen::Matrix4d readItkTransformFile(const std::string& path) {
  std::ifstream file(path);
  require(file.good(), "cannot read transform file '" + path + "': the file does not exist or is not readable");
  std::string line;
  std::getline(file, line);
  require(trimmed(line).rfind("#Insight Transform File", 0) == 0,
          "'" + path + "' is not an ITK text transform file (no '#Insight Transform File' first line)");
  std::string type;
  std::vector<double> parameters, fixed;
  bool haveParameters = false, haveFixed = false;
  while (std::getline(file, line)) {
    const auto colon = line.find(':');
    if (trimmed(line).empty() || line[0] == '#' || colon == std::string::npos) continue;
    const std::string key = trimmed(line.substr(0, colon));
    const std::string value = line.substr(colon + 1);
    if (key == "Transform") {
      if (!type.empty()) break;  // only the first transform of the file
      type = trimmed(value);
    } else if (key == "Parameters" && !haveParameters) {
      parameters = numbers(value, path, key);
      haveParameters = true;
    } else if (key == "FixedParameters" && !haveFixed) {
      fixed = numbers(value, path, key);
      haveFixed = true;
    }
  }
  require(!type.empty() && haveParameters, "transform file '" + path + "' has no 'Transform:' with 'Parameters:'");
  const bool linear3d = type.find("_double_3_3") != std::string::npos || type.find("_float_3_3") != std::string::npos;
  Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();
  if (type.rfind("TranslationTransform_", 0) == 0 && parameters.size() == 3) {
    matrix.topRightCorner<3, 1>() = Eigen::Vector3d(parameters[0], parameters[1], parameters[2]);
    return matrix;
  }
  require(linear3d && parameters.size() == 12 && type.find("Composite") == std::string::npos &&
              type.find("BSpline") == std::string::npos && type.find("DisplacementField") == std::string::npos,
          "transform file '" + path + "' holds a '" + type + "' with " + std::to_string(parameters.size()) +
              " parameters; only 3D linear transforms (12 parameters: matrix and translation) are supported");
  Eigen::Matrix3d linear;
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) linear(row, col) = parameters[static_cast<std::size_t>(3 * row + col)];
  }
  const Eigen::Vector3d translation(parameters[9], parameters[10], parameters[11]);
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  if (haveFixed && !fixed.empty()) {
    require(fixed.size() == 3, "transform file '" + path + "': FixedParameters must be the 3 centre coordinates");
    center = Eigen::Vector3d(fixed[0], fixed[1], fixed[2]);
  }
  // ITK: y = A (x - c) + t + c.
  matrix.topLeftCorner<3, 3>() = linear;
  matrix.topRightCorner<3, 1>() = translation + center - linear * center;
  require(matrix.allFinite() && std::abs(linear.determinant()) > 1e-12,
          "transform file '" + path + "' holds a singular or non-finite matrix");
  return matrix;
}

void writeModelToTargetTransform(const std::string& path, const Eigen::Matrix4d& targetFromModelLps) {
  require(isAffine(targetFromModelLps) && std::abs(targetFromModelLps.topLeftCorner<3, 3>().determinant()) > 1e-12,
          "cannot write '" + path + "': the model-to-target transform is singular or not affine");
  writeItkTransformFile(path, targetFromModelLps.inverse());
}

Eigen::Matrix4d readModelToTargetTransform(const std::string& path) {
  return readItkTransformFile(path).inverse();
}

}  // namespace tissuemosaic
