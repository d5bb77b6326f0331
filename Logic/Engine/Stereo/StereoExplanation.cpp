#include "StereoExplanation.h"

#include <cstdio>

namespace tissuemosaic {

std::string StereoExplanation::json() const {
  char text[512];
  std::snprintf(text, sizeof text,
                "{\"pixels\": %ld, \"estimated\": %ld, \"density\": %.4f, \"removed\": {\"outside_right_image\": %ld, "
                "\"textureless_window\": %ld, \"range_end\": %ld, \"left_right_check\": %ld, \"highlight\": %ld, "
                "\"outlier_sweeps\": %ld}, "
                "\"filled_back\": %ld, \"not_filled\": %ld}",
                pixels, estimated, pixels > 0 ? static_cast<double>(estimated) / pixels : 0.0, outsideRightImage,
                texturelessWindow, rangeEnd, leftRightCheck, highlight, outlierSweeps, filledBack, notFilled);
  return text;
}

}  // namespace tissuemosaic
