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
  EXPECT_TRUE(std::filesystem::exists(dir / "c.png")) << note;
  EXPECT_TRUE(note.empty()) << note;
  std::ifstream png(dir / "c.png", std::ios::binary);
  char magic[8] = {};
  png.read(magic, 8);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  std::filesystem::remove_all(dir);
}

// The PNG used to come from system("rsvg-convert -o '<out>'..."): a quote in the output
// folder ran the rest of the path as shell commands, and a plain apostrophe lost the PNG.
TEST(Chart, AQuoteInThePathReachesNoShellAndStillGetsItsPng) {
  auto dir = std::filesystem::temp_directory_path() / ("chart_quote_" + std::to_string(::getpid()));
  const auto marker = dir / "injected";
  auto odd = dir / ("it's '; touch " + marker.string() + "; echo '");
  std::filesystem::create_directories(odd);
  std::string note = write_chart((odd / "loss.svg").string(), {{"a", {1, 2}, {1, 2}, {}}}, ChartOptions{});
  EXPECT_TRUE(note.empty()) << note;
  EXPECT_TRUE(std::filesystem::exists(odd / "loss.png"));
  EXPECT_FALSE(std::filesystem::exists(marker)) << "the path was run by a shell";
  std::filesystem::remove_all(dir);
}
