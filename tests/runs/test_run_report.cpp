// A training run's report: one row per epoch (its last record), thinned evenly for long
// runs with the last epoch always shown; a stopped run says so and why.
#include <gtest/gtest.h>

#include "runs/run_report.h"

using namespace nns;
using namespace nns::runs;

TEST(RunReport, OneRowPerEpochFromItsLastRecord) {
  std::vector<MetricsRecord> log = {
      {10, 1, {{"d", 0.5}, {"g", 2}}}, {20, 1, {{"d", 0.25}, {"g", 1}}}, {30, 2, {{"d", 0.125}, {"g", NAN}}}};
  const report::Table t = epoch_table(log);
  EXPECT_EQ(t.header, (std::vector<std::string>{"epoch", "step", "d", "g"}));
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[0], (std::vector<std::string>{"1", "20", "0.25", "1"}));
  EXPECT_EQ(t.rows[1], (std::vector<std::string>{"2", "30", "0.125", "–"}));  // a dash, not "nan"
}

TEST(RunReport, LongRunsAreThinnedEvenlyKeepingTheEnds) {
  std::vector<MetricsRecord> log;
  for (int e = 1; e <= 200; ++e) log.push_back({e * 10, e, {{"loss", 1.0 / e}}});
  const report::Table t = epoch_table(log, 25);
  ASSERT_EQ(t.rows.size(), 25u);
  EXPECT_EQ(t.rows.front()[0], "1");
  EXPECT_EQ(t.rows.back()[0], "200");
  for (size_t i = 1; i < t.rows.size(); ++i) EXPECT_LT(std::stoi(t.rows[i - 1][0]), std::stoi(t.rows[i][0]));
}

TEST(RunReport, AStoppedRunSaysWhyAndTheTrainerAddsItsBlocks) {
  const report::Report r =
      training_report({"train-gan", "NaN at step 5", 1, 5, {{"seconds", 1.5}}}, {}, {{"lr", "0.0002"}},
                      [](report::Report& rep) { rep.chart("loss.svg", "losses"); });
  const std::string md = r.markdown();
  EXPECT_NE(md.find("**Stopped** after 1 epoch, 5 steps: NaN at step 5."), std::string::npos) << md;
  EXPECT_NE(md.find("![losses](loss.svg)"), std::string::npos) << md;
  EXPECT_NE(md.find("No epoch finished."), std::string::npos) << md;
  EXPECT_NE(md.find("| seconds | 1.5 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| lr | 0.0002 |"), std::string::npos) << md;
}

// Configuration values are recorded with 17 significant digits (they read back as the
// same double); the page shows the fewest digits that still do, and other text as it is.
TEST(RunReport, ConfigurationValuesReadAsPeopleWriteThem) {
  EXPECT_EQ(readable_value("0.29999999999999999"), "0.3");
  EXPECT_EQ(readable_value("0.0001"), "0.0001");
  EXPECT_EQ(readable_value("1.0000000000000001e-05"), "1e-05");
  EXPECT_EQ(readable_value("16"), "16");
  EXPECT_EQ(readable_value("100000"), "100000");
  EXPECT_EQ(readable_value("0.1234567890123456"), "0.1234567890123456");
  EXPECT_EQ(readable_value("horizon"), "horizon");
  EXPECT_EQ(readable_value("/data/run 0.3"), "/data/run 0.3");
  EXPECT_EQ(readable_value(""), "");
  const report::Report r =
      training_report({"train-nnao", "", 1, 8, {}}, {}, {{"gamma", "0.0001"}, {"dropout", "0.29999999999999999"}}, {});
  EXPECT_NE(r.markdown().find("| dropout | 0.3 |"), std::string::npos) << r.markdown();
  EXPECT_NE(r.markdown().find("**Finished**: 1 epoch, 8 steps."), std::string::npos) << r.markdown();
}
