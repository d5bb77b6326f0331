#pragma once
/// @file SyntheticHaze.h
/// @brief Smoke for the synthetic scans: a smooth density field (a few octaves of value noise, features of 60 px
/// and more) that drifts and churns over time, laid over an 8-bit image as scattered light. Deterministic from the
/// seed; the same field for both eyes (smoke fills the space between the scope and the tissue and has no texture
/// that stereo could lock onto).
#include <opencv2/core.hpp>

#include <cstdint>

namespace tissuemosaic::synthetic {

/// Density in [0, 1] per pixel (CV_32F) of the drifting smoke at time t (s).
cv::Mat hazeDensity(cv::Size size, double timeS, uint32_t seed);

/// image (CV_8UC3, in place) seen through smoke: each pixel moves toward smokeBgr by density * strength.
void applyHaze(cv::Mat& image, const cv::Mat& density, double strength, const cv::Vec3d& smokeBgr);

}  // namespace tissuemosaic::synthetic
