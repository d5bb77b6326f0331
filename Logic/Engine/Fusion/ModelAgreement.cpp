#include "ModelAgreement.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"

#include <opencv2/core/persistence.hpp>

namespace tissuemosaic {

namespace {

template <class T>
void requireRange(const char* name, T value, T low, T high) {
  parameters::requireRange("agreement", name, value, low, high);
}

template <class T>
void readKey(const cv::FileNode& node, const char* name, T& value) {
  parameters::readKey("agreement", node, name, value);
}

}  // namespace

const char* agreementLevelName(AgreementLevel level) {
  switch (level) {
    case AgreementLevel::Good: return "good";
    case AgreementLevel::Fair: return "fair";
    case AgreementLevel::Poor: return "poor";
    default: return "none";
  }
}

AgreementLevel AgreementParameters::level(const ModelAgreement& a) const {
  if (!a.measured) return AgreementLevel::None;
  if (a.shareWithin1mm < poorShare || a.medianDepthDifferenceMm > poorMedianMm) return AgreementLevel::Poor;
  if (a.shareWithin1mm >= goodShare && a.medianDepthDifferenceMm <= goodMedianMm) return AgreementLevel::Good;
  return AgreementLevel::Fair;
}

bool AgreementParameters::collapsed(const ModelAgreement& a) const {
  return a.measured && a.overlap() >= minOverlap && a.shareWithin1mm < lostShare &&
         a.medianDepthDifferenceMm > lostMedianMm;
}

void AgreementParameters::validate() const {
  requireRange("sampleStridePx", sampleStridePx, 1, 64);
  requireRange("goodShare", goodShare, 0.0, 1.0);
  requireRange("goodMedianMm", goodMedianMm, 0.0, 1000.0);
  requireRange("poorShare", poorShare, 0.0, goodShare);
  requireRange("poorMedianMm", poorMedianMm, goodMedianMm, 1000.0);
  requireRange("lostShare", lostShare, 0.0, 1.0);
  requireRange("lostMedianMm", lostMedianMm, 0.0, 1000.0);
  requireRange("minOverlap", minOverlap, 0.0, 1.0);
  requireRange("relocalisationMinShare", relocalisationMinShare, 0.0, 1.0);
}

void AgreementParameters::write(cv::FileStorage& storage) const {
  storage << "agreement" << "{";
  storage << "sampleStridePx" << sampleStridePx << "goodShare" << goodShare << "goodMedianMm" << goodMedianMm;
  storage << "poorShare" << poorShare << "poorMedianMm" << poorMedianMm << "lostShare" << lostShare;
  storage << "lostMedianMm" << lostMedianMm << "minOverlap" << minOverlap;
  storage << "relocalisationMinShare" << relocalisationMinShare;
  storage << "}";
}

AgreementParameters AgreementParameters::read(const cv::FileNode& node) {
  AgreementParameters p;
  if (node.empty()) return p;
  if (!node.isMap()) throw Error("the 'agreement' parameter node must be a map");
  readKey(node, "sampleStridePx", p.sampleStridePx);
  readKey(node, "goodShare", p.goodShare);
  readKey(node, "goodMedianMm", p.goodMedianMm);
  readKey(node, "poorShare", p.poorShare);
  readKey(node, "poorMedianMm", p.poorMedianMm);
  readKey(node, "lostShare", p.lostShare);
  readKey(node, "lostMedianMm", p.lostMedianMm);
  readKey(node, "minOverlap", p.minOverlap);
  readKey(node, "relocalisationMinShare", p.relocalisationMinShare);
  p.validate();
  return p;
}

}  // namespace tissuemosaic
