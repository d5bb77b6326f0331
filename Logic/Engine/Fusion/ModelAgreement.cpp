#include "ModelAgreement.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"

#include <opencv2/core/persistence.hpp>

namespace tissuemosaic {

namespace {

constexpr parameters::Group kAgreement{"agreement"};

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
  kAgreement.requireRange("sampleStridePx", sampleStridePx, 1, 64);
  kAgreement.requireRange("goodShare", goodShare, 0.0, 1.0);
  kAgreement.requireRange("goodMedianMm", goodMedianMm, 0.0, 1000.0);
  kAgreement.requireRange("poorShare", poorShare, 0.0, goodShare);
  kAgreement.requireRange("poorMedianMm", poorMedianMm, goodMedianMm, 1000.0);
  kAgreement.requireRange("lostShare", lostShare, 0.0, 1.0);
  kAgreement.requireRange("lostMedianMm", lostMedianMm, 0.0, 1000.0);
  kAgreement.requireRange("minOverlap", minOverlap, 0.0, 1.0);
  kAgreement.requireRange("relocalisationMinShare", relocalisationMinShare, 0.0, 1.0);
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
  kAgreement.readKey(node, "sampleStridePx", p.sampleStridePx);
  kAgreement.readKey(node, "goodShare", p.goodShare);
  kAgreement.readKey(node, "goodMedianMm", p.goodMedianMm);
  kAgreement.readKey(node, "poorShare", p.poorShare);
  kAgreement.readKey(node, "poorMedianMm", p.poorMedianMm);
  kAgreement.readKey(node, "lostShare", p.lostShare);
  kAgreement.readKey(node, "lostMedianMm", p.lostMedianMm);
  kAgreement.readKey(node, "minOverlap", p.minOverlap);
  kAgreement.readKey(node, "relocalisationMinShare", p.relocalisationMinShare);
  p.validate();
  return p;
}

}  // namespace tissuemosaic
