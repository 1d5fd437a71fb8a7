#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "report/chart.h"

using namespace nns::data;

TEST(Chart, SvgHasLegendLabelsAndLogTicks) {
  std::vector<ChartSeries> s = {{"NNAO", {1, 10, 100}, {0.01, 0.005, 0.004}, {"64", "128", "256"}},
                                {"HBAO & co", {2, 20}, {0.02, 0.01}, {}}};
  ChartOptions o;
  o.title = "speed vs accuracy";
  o.x_label = "ms per frame";
  o.y_label = "MSE";
  o.log_x = true;
  std::string svg = line_chart_svg(s, o);
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find(">NNAO<"), std::string::npos);
  EXPECT_NE(svg.find("HBAO &amp; co"), std::string::npos);  // escaped
  EXPECT_NE(svg.find(">128<"), std::string::npos);
  EXPECT_NE(svg.find("(log scale)"), std::string::npos);
  EXPECT_NE(svg.find(">100<"), std::string::npos);  // a decade tick
  EXPECT_EQ(svg.find("nan"), std::string::npos);
}

TEST(Chart, SkipsNonPositiveOnLogAxisAndWritesFiles) {
  std::vector<ChartSeries> s = {{"a", {0, 1, 10}, {1, 2, 3}, {}}};
  ChartOptions o;
  o.log_x = true;
  auto dir = std::filesystem::temp_directory_path() / ("chart_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::string path = (dir / "c.svg").string();
  std::string note = write_chart(path, s, o);
  EXPECT_TRUE(std::filesystem::exists(path));
  bool have_rsvg = std::system("command -v rsvg-convert > /dev/null 2>&1") == 0;
  EXPECT_EQ(std::filesystem::exists(dir / "c.png"), have_rsvg) << note;
  EXPECT_EQ(note.empty(), have_rsvg) << note;
  std::filesystem::remove_all(dir);
}
