// A training run's report: one row per epoch (its last record), thinned evenly for long
// runs with the last epoch always shown; a stopped run says so and why.
#include <gtest/gtest.h>

#include "runs/run_report.h"

using namespace nns;
using namespace nns::runs;

TEST(RunReport, OneRowPerEpochFromItsLastRecord) {
  std::vector<MetricsRecord> log = {{10, 1, {{"d", 0.5}, {"g", 2}}}, {20, 1, {{"d", 0.25}, {"g", 1}}},
                                    {30, 2, {{"d", 0.125}, {"g", NAN}}}};
  const data::Table t = epoch_table(log);
  EXPECT_EQ(t.header, (std::vector<std::string>{"epoch", "step", "d", "g"}));
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[0], (std::vector<std::string>{"1", "20", "0.25", "1"}));
  EXPECT_EQ(t.rows[1], (std::vector<std::string>{"2", "30", "0.125", "nan"}));
}

TEST(RunReport, LongRunsAreThinnedEvenlyKeepingTheEnds) {
  std::vector<MetricsRecord> log;
  for (int e = 1; e <= 200; ++e) log.push_back({e * 10, e, {{"loss", 1.0 / e}}});
  const data::Table t = epoch_table(log, 25);
  ASSERT_EQ(t.rows.size(), 25u);
  EXPECT_EQ(t.rows.front()[0], "1");
  EXPECT_EQ(t.rows.back()[0], "200");
  for (size_t i = 1; i < t.rows.size(); ++i) EXPECT_LT(std::stoi(t.rows[i - 1][0]), std::stoi(t.rows[i][0]));
}

TEST(RunReport, AStoppedRunSaysWhyAndTheTrainerAddsItsBlocks) {
  const data::Report r = training_report({"train-gan", "NaN at step 5", 1, 5, {{"seconds", 1.5}}}, {},
                                         {{"lr", "0.0002"}}, [](data::Report& rep) { rep.chart("loss.svg", "losses"); });
  const std::string md = r.markdown();
  EXPECT_NE(md.find("**Stopped** after 1 epochs, 5 steps: NaN at step 5."), std::string::npos) << md;
  EXPECT_NE(md.find("![losses](loss.svg)"), std::string::npos) << md;
  EXPECT_NE(md.find("No epoch finished."), std::string::npos) << md;
  EXPECT_NE(md.find("| seconds | 1.5 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| lr | 0.0002 |"), std::string::npos) << md;
}
