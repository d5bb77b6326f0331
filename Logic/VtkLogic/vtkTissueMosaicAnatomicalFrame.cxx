#include "vtkTissueMosaicAnatomicalFrame.h"

#include "Core/Error.h"

#include <algorithm>
#include <cctype>

namespace tissuemosaic {

namespace {

std::string lowered(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

}  // namespace

const char* frameName(AnatomicalFrame frame) { return frame == AnatomicalFrame::LPS ? "LPS" : "RAS"; }

AnatomicalFrame parseFrame(const std::string& text) {
  const std::string word = lowered(text);
  if (word == "lps") return AnatomicalFrame::LPS;
  if (word == "ras") return AnatomicalFrame::RAS;
  throw Error("unknown coordinate frame '" + text + "': use lps or ras");
}

ModelFrameChoice parseModelFrameChoice(const std::string& text) {
  const std::string word = lowered(text);
  if (word == "file") return ModelFrameChoice::FromFile;
  if (word == "lps") return ModelFrameChoice::LPS;
  if (word == "ras") return ModelFrameChoice::RAS;
  throw Error("unknown model frame '" + text + "': use file (what the file declares, LPS if nothing), lps or ras");
}

}  // namespace tissuemosaic
