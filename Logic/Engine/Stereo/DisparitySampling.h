#pragma once
/// @file DisparitySampling.h
/// @brief The stereo matcher's sampling of its disparity map on CUDA, by Core/DisparitySampling.h's rule.
#include "Core/DisparitySampling.h"

namespace tissuemosaic {

/// Samples `count` points (x, y pairs in pointsXyPx) into disparitiesPx, on the device that holds the map.
void sampleDisparitiesCuda(ImageView<const float> disparityPx, const float* pointsXyPx, float* disparitiesPx, int count);

}  // namespace tissuemosaic
