// eval-ao's speed/accuracy front (runs/ao/ao_pareto.h) on hand-made rows: which settings
// are on the front, and which NNAO setting beats each classical one at no more time.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "runs/ao/ao_pareto.h"
#include "tests/support/csv_line.h"

using nns::runs::ParetoRow;

namespace {

ParetoRow row(const std::string& m, const std::string& s, double ms, double mse, double ssim) {
  return {m, s, ms, 2 * ms, mse, ssim, NAN};
}

const ParetoRow& find(const std::vector<ParetoRow>& rows, const std::string& m, const std::string& s) {
  for (auto& r : rows)
    if (r.method == m && r.setting == s) return r;
  throw std::runtime_error("no row " + m + "@" + s);
}

}  // namespace

TEST(AoPareto, FrontAndWinsAtNoMoreTime) {
  std::vector<ParetoRow> rows = {
      row("SSAO", "4", 2.0, 0.030, 0.60),     // cheapest: on the front whatever its error
      row("GTAO", "8", 6.0, 0.012, 0.80),     //
      row("GTAO", "32", 16.0, 0.0080, 0.88),  //
      row("NNAO-exact", "quarter", 3.0, 0.0100, 0.85),
      row("NNAO-exact", "half", 10.0, 0.0070, 0.89),
      row("NNAO-exact", "slow", 40.0, 0.0075, 0.90),  // slower and worse than "half": off the front
  };
  nns::runs::mark_front_and_wins(rows);
  EXPECT_TRUE(find(rows, "SSAO", "4").on_front);
  EXPECT_FALSE(find(rows, "GTAO", "8").on_front);   // "quarter" is faster and better
  EXPECT_FALSE(find(rows, "GTAO", "32").on_front);  // "half" is faster and better
  EXPECT_TRUE(find(rows, "NNAO-exact", "quarter").on_front);
  EXPECT_TRUE(find(rows, "NNAO-exact", "half").on_front);
  EXPECT_FALSE(find(rows, "NNAO-exact", "slow").on_front);
  // SSAO-4 is faster than every NNAO setting: nothing beats it at no more time.
  EXPECT_EQ(find(rows, "SSAO", "4").beaten_by, "none");
  // GTAO-8: "quarter" is the fastest NNAO within 6 ms with lower MSE and higher SSIM.
  EXPECT_EQ(find(rows, "GTAO", "8").beaten_by, "NNAO-exact@quarter");
  // GTAO-32: "quarter" is faster but has the higher MSE; "half" beats it in both.
  EXPECT_EQ(find(rows, "GTAO", "32").beaten_by, "NNAO-exact@half");
  EXPECT_EQ(find(rows, "NNAO-exact", "half").beaten_by, "");  // NNAO rows are not judged
}

TEST(AoPareto, ABetterMseWithAWorseSsimIsNoWin) {
  std::vector<ParetoRow> rows = {row("HBAO", "16", 5.0, 0.010, 0.90), row("NNAO-exact", "a", 4.0, 0.009, 0.89),
                                 row("NNAO-exact", "b", 5.0, 0.011, 0.95), row("NNAO-exact", "c", 5.5, 0.005, 0.99)};
  nns::runs::mark_front_and_wins(rows);
  EXPECT_EQ(rows[0].beaten_by, "none");  // a: SSIM lower; b: MSE higher; c: slower
  const std::string csv = nns::runs::pareto_csv(rows);
  EXPECT_EQ(
      csv.rfind("method,setting,wall_ms,cpu_ms,mse,ssim,flicker_x_truth,on_front,beaten_by_nnao_at_no_more_time\n", 0),
      0u);
  EXPECT_NE(csv.find("\nHBAO,16,5,10,0.01,0.9,,no,none\n"), std::string::npos) << csv;
}

// A method or setting with a comma (an NNAO model's file name) shifted the columns.
TEST(AoPareto, CsvKeepsItsColumnsWhateverTheMethodIsCalled) {
  std::vector<ParetoRow> rows = {{"NNAO-exact (runs/a,b)", "k=1,r=2", 1.0, 1.0, 0.01, 0.9, NAN}};
  const auto lines = nns::testing::csv_lines(nns::runs::pareto_csv(rows));
  ASSERT_EQ(lines.size(), 2u);
  const auto f = nns::testing::csv_fields(lines[1]);
  EXPECT_EQ(f.size(), nns::testing::csv_fields(lines[0]).size()) << lines[1];
  EXPECT_EQ(f[0], "NNAO-exact (runs/a,b)");
  EXPECT_EQ(f[1], "k=1,r=2");
}
