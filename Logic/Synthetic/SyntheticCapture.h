#pragma once
/// @file SyntheticCapture.h
/// @brief How the in-vivo scans' camera captures a frame in time (SyntheticInVivo.h): over an exposure (motion
/// blur: the scene rendered at several instants across the exposure and averaged) and, interlaced, as two fields
/// (even rows exposed at the frame's time t, odd rows half a frame period later, as an analogue / SD capture
/// gives). The frame's ground truth (pose, depth, surface) is for the even field's mid-exposure: t itself.
#include <opencv2/core.hpp>

#include <vector>

namespace tissuemosaic::synthetic {

/// The longest time between two instants of a blurred exposure: finer than a pixel's travel for the motions here.
constexpr double kMotionBlurStepMs = 4.0;

/// The instants of one exposure of exposureMs centred on its field's time, as offsets from it (s): an odd count
/// (at least 3 for any exposure > 0, so that the middle one is the field's time itself), evenly spread over
/// [-exposure / 2, +exposure / 2], at most kMotionBlurStepMs apart. {0} for no exposure time (no blur).
std::vector<double> exposureOffsetsS(double exposureMs);

/// The fields of a frame as offsets from its time (s): {0} progressive, {0, 1 / (2 fps)} interlaced (even rows, then
/// odd rows).
std::vector<double> fieldOffsetsS(bool interlaced, double fps);

/// Sums 8-bit BGR renders of one field into a CV_32FC3 accumulator (created on first use); rowParity 0 or 1 adds
/// only those rows, -1 all.
void accumulateField(const cv::Mat& render, int rowParity, cv::Mat& sum);
/// The average of `count` accumulated renders, rounded to 8 bits (a pixel that did not change reads exactly as in
/// each render).
cv::Mat averagedImage(const cv::Mat& sum, int count);

}  // namespace tissuemosaic::synthetic
