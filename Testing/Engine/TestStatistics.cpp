// The summary statistics of every benchmark and timing table (Core/Statistics.h), on hand-computed cases.
#include "Core/Statistics.h"
#include "Reconstruction/TimingTable.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

using namespace tissuemosaic;

TEST(Statistics, Percentile99IsTheNearestRank) {
  std::vector<double> hundred;
  for (int i = 1; i <= 100; ++i) hundred.push_back(i);
  std::shuffle(hundred.begin(), hundred.end(), std::mt19937(3));
  EXPECT_EQ(percentile99(hundred), 99.0);  // rank ceil(0.99 * 100) = 99
  hundred.push_back(1000);                 // 101 values: rank ceil(99.99) = 100, the value 100
  EXPECT_EQ(percentile99(hundred), 100.0);
  EXPECT_EQ(percentile99({4, 1, 3, 2}), 4.0);  // fewer than 100 values: the largest
  EXPECT_EQ(percentile99({7}), 7.0);
  EXPECT_EQ(percentile99({}), 0.0);
}

TEST(Statistics, MedianAndMeanOnHandComputedCases) {
  EXPECT_EQ(median({3, 1, 2}), 2.0);
  EXPECT_EQ(median({4, 1, 3, 2}), 2.5);
  EXPECT_EQ(mean({1, 2, 3, 10}), 4.0);
  EXPECT_EQ(largest({1, 9, 3}), 9.0);
}

TEST(TimingTable, ReportsTheWorstFrameInAHundredBesideMedianAndMean) {
  TimingTable table;
  for (int i = 1; i <= 100; ++i) {
    StageTimesMs times;
    times.total = i == 100 ? 50.0 : 2.0;  // one spike in a hundred frames
    table.add(times, false);
  }
  const std::size_t total = TimingTable::stageNames().size() - 1;
  EXPECT_EQ(table.medians(false)[total], 2.0);
  EXPECT_DOUBLE_EQ(table.means(false)[total], 2.48);
  EXPECT_EQ(table.percentiles99(false)[total], 2.0);  // the 99th of 100 is still an ordinary frame
  StageTimesMs spike;
  spike.total = 50.0;
  table.add(spike, false);  // two spikes in 101 frames: the 100th value is a spike
  EXPECT_EQ(table.percentiles99(false)[total], 50.0);
  EXPECT_NE(table.toJson().find("\"p99_ms\": {"), std::string::npos);
  EXPECT_NE(table.format().find("p99"), std::string::npos);
}
