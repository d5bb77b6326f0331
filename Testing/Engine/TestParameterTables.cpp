// The parameter tables (Core/ParameterTable.h, issue 53): every member of each parameter struct has a row; every row
// goes through the parameter file and back; validate() refuses a value just outside a row's limits, with those
// limits in its message, and takes the limits themselves.
#include "Fusion/FusionParameterTable.h"
#include "Refinement/RefinementParameterTable.h"
#include "Stereo/StereoParameterTable.h"
#include "Tracking/FeatureParameterTable.h"
#include "Tracking/TrackingParameterTable.h"

#include <gtest/gtest.h>

#include <opencv2/core/persistence.hpp>

#include <algorithm>
#include <set>
#include <sstream>
#include <string>

namespace tissuemosaic {
namespace {

using parameters::Field;
using parameters::FieldKind;
using parameters::Table;

template <class S>
class ParameterTable : public ::testing::Test {};

template <class S>
const Table<S>& tableOf();
template <>
const Table<StereoParameters>& tableOf() { return stereoParameterTable(); }
template <>
const Table<TrackingParameters>& tableOf() { return trackingParameterTable(); }
template <>
const Table<RefinementParameters>& tableOf() { return refinementParameterTable(); }
template <>
const Table<FusionParameters>& tableOf() { return fusionParameterTable(); }
template <>
const Table<FeatureParameters>& tableOf() { return featureParameterTable(); }

using Structs =
    ::testing::Types<StereoParameters, TrackingParameters, RefinementParameters, FusionParameters, FeatureParameters>;
TYPED_TEST_SUITE(ParameterTable, Structs);

/// A value of the field other than its default, within its limits (a choice: another name).
template <class S>
double otherValue(const Field<S>& field) {
  const double value = field.defaultValue();
  if (field.kind == FieldKind::Choice) {
    for (int choice : field.choiceValues) {
      if (choice != static_cast<int>(value)) return choice;
    }
    return value;
  }
  if (field.integer()) return value + 1 <= field.maximum ? value + 1 : value - 1;
  return value < field.maximum ? (value + field.maximum) / 2 : (value + field.minimum) / 2;
}

/// The row's node written and read back through OpenCV's YAML (the struct's own read, without validate()).
template <class S>
S throughFile(const Table<S>& table, const S& written) {
  cv::FileStorage out(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  table.write(written, out);
  const cv::FileStorage in(out.releaseAndGetString(), cv::FileStorage::READ | cv::FileStorage::MEMORY);
  S read;
  table.read(in[table.node()], read);
  return read;
}

TYPED_TEST(ParameterTable, EveryMemberHasOneRow) {
  using S = TypeParam;
  std::vector<const Field<S>*> rows;
  std::set<std::string> keys;
  for (const Field<S>& field : tableOf<S>().fields()) {
    rows.push_back(&field);
    EXPECT_TRUE(keys.insert(field.key).second) << "two rows for " << field.key;
  }
  std::sort(rows.begin(), rows.end(), [](const Field<S>* a, const Field<S>* b) { return a->offset < b->offset; });
  // The rows tile the struct: between two members lies only the padding the second one's alignment needs (a member
  // without a row leaves a gap), and after the last one only the struct's own padding.
  std::size_t end = 0;
  for (const Field<S>* field : rows) {
    const std::size_t aligned = (end + field->size - 1) / field->size * field->size;  // scalars align to their size
    EXPECT_EQ(field->offset, aligned) << "a member without a row lies before " << field->key << " (or rows overlap)";
    end = field->offset + field->size;
  }
  EXPECT_LT(sizeof(S) - end, alignof(S)) << "a member without a row lies after " << rows.back()->key;
}

TYPED_TEST(ParameterTable, EveryRowGoesThroughTheFileAndBack) {
  using S = TypeParam;
  const Table<S>& table = tableOf<S>();
  for (const Field<S>& field : table.fields()) {
    S written;
    const double value = otherValue(field);
    ASSERT_NE(value, field.defaultValue()) << field.key << ": no other value to try";
    field.set(written, value);
    const S read = throughFile(table, written);
    if (field.kind == FieldKind::Float) {
      EXPECT_FLOAT_EQ(static_cast<float>(field.get(read)), static_cast<float>(value)) << field.key;
    } else {
      EXPECT_EQ(field.get(read), value) << field.key;
    }
  }
}

TYPED_TEST(ParameterTable, ValidateTakesTheLimitsAndRefusesBeyondThemWithTheTablesWords) {
  using S = TypeParam;
  const Table<S>& table = tableOf<S>();
  EXPECT_NO_THROW(S{}.validate()) << "the defaults are valid";
  for (const Field<S>& field : table.fields()) {
    if (field.kind == FieldKind::Choice) continue;
    EXPECT_LE(field.minimum, field.defaultValue()) << field.key;
    EXPECT_GE(field.maximum, field.defaultValue()) << field.key;
    // Each limit passes the table's own check (the rules between fields may still refuse it).
    for (double limit : {field.minimum, field.maximum}) {
      S atLimit;
      field.set(atLimit, limit);
      EXPECT_NO_THROW(table.requireInRange(atLimit)) << field.key << " = " << limit;
    }
    const double step = field.integer() ? 1.0 : std::max(1e-6, 1e-3 * (field.maximum - field.minimum));
    for (double outside : {field.minimum - step, field.maximum + step}) {
      if (field.size == sizeof(bool) && field.integer()) continue;  // a bool holds no third value
      S beyond;
      field.set(beyond, outside);
      if (field.kind == FieldKind::Float && static_cast<double>(static_cast<float>(outside)) == field.maximum) {
        continue;  // the step vanished in a float
      }
      try {
        beyond.validate();
        ADD_FAILURE() << field.key << " = " << outside << " was accepted";
      } catch (const Error& error) {
        std::ostringstream limits;
        if (field.integer()) {
          limits << "[" << static_cast<long long>(field.minimum) << ", " << static_cast<long long>(field.maximum) << "]";
        } else {
          limits << "[" << field.minimum << ", " << field.maximum << "]";
        }
        const std::string expected = std::string(table.group()) + " parameter " + field.key + " = ";
        EXPECT_NE(std::string(error.what()).find(expected), std::string::npos) << error.what();
        EXPECT_NE(std::string(error.what()).find("is out of range " + limits.str()), std::string::npos)
            << error.what();
      }
    }
  }
}

TEST(ParameterTable, ChoicesAreWrittenByNameAndUnknownNamesAreRefused) {
  for (const StereoMethod method : {StereoMethod::Paper, StereoMethod::AdCensus}) {
    StereoParameters written;
    written.method = method;
    EXPECT_EQ(throughFile(stereoParameterTable(), written).method, method);
  }
  const cv::FileStorage in("%YAML:1.0\nstereo: {method: sgm}\n", cv::FileStorage::READ | cv::FileStorage::MEMORY);
  StereoParameters read;
  try {
    stereoParameterTable().read(in["stereo"], read);
    FAIL() << "an unknown method was read";
  } catch (const Error& error) {
    EXPECT_STREQ(error.what(), "stereo parameter method must be \"paper\" or \"ad-census\", not 'sgm'");
  }
}

}  // namespace
}  // namespace tissuemosaic
