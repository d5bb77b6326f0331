#pragma once
/// @file vtkTissueMosaicRunCatching.h
/// @brief The logic classes' boundary: their calls return false with an error text instead of throwing.
#include "Core/Error.h"

#include <opencv2/core.hpp>

#include <exception>
#include <string>

namespace tissuemosaic {

/// Runs work(); turns what the engine and OpenCV throw into an error text (cleared on success).
template <class Work>
bool runCatching(Work&& work, std::string& errorText) {
  try {
    work();
    errorText.clear();
    return true;
  } catch (const Error& error) {
    errorText = error.what();
  } catch (const cv::Exception& error) {
    errorText = std::string("OpenCV: ") + error.what();
  } catch (const std::exception& error) {
    errorText = error.what();
  }
  return false;
}

}  // namespace tissuemosaic
