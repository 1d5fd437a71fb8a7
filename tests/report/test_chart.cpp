#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "report/chart.h"

using namespace nns::report;

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

// A variant series (a method with temporal accumulation) is drawn dashed, in the colour
// it is given (its method's), line and legend alike; plain series are solid.
TEST(Chart, DashedVariantTakesTheGivenColour) {
  std::vector<ChartSeries> s = {{"GTAO", {1, 2}, {0.02, 0.01}, {}},
                                {"HBAO", {1, 2}, {0.03, 0.02}, {}},
                                {"GTAO+TA", {1.1, 2.1}, {0.019, 0.009}, {}}};
  s[2].colour = 0;
  s[2].dashed = true;
  const std::string svg = line_chart_svg(s, ChartOptions{});
  size_t dashes = 0;
  for (size_t at = svg.find("stroke-dasharray"); at != std::string::npos; at = svg.find("stroke-dasharray", at + 1))
    ++dashes;
  EXPECT_EQ(dashes, 2u);  // its polyline and its legend line
  // The first series' colour appears on the variant's dashed polyline.
  const size_t first = svg.find("<polyline"), third = svg.rfind("<polyline");
  auto stroke = [&](size_t at) { return svg.substr(svg.find("stroke=\"", at), 16); };
  EXPECT_EQ(stroke(first), stroke(third));
  EXPECT_NE(svg.find("stroke-dasharray=\"6,4\"", third), std::string::npos);
}

// A log axis that spans less than a decade (a loss between 0.3 and 0.9) used to get one
// tick or none: it takes finer steps, so the chart can be read.
TEST(Chart, ALogAxisWithinADecadeHasTicksToReadItBy) {
  ChartOptions o;
  o.log_y = true;
  const std::string svg = line_chart_svg({{"loss", {1, 2, 3}, {0.9, 0.5, 0.3}, {}}}, o);
  size_t ticks = 0;
  for (size_t at = svg.find("text-anchor=\"end\">"); at != std::string::npos;
       at = svg.find("text-anchor=\"end\">", at + 1))
    ++ticks;
  EXPECT_GE(ticks, 3u) << svg;
}

// A long legend name gets the room it needs (wrapped beyond 45% of the chart), never
// running past the image's right edge.
TEST(Chart, ALongLegendNameWrapsInsideTheImage) {
  ChartOptions o;
  const std::string name = "train loss (MSE + gamma|theta|, standardised) of the horizon model, every epoch";
  const std::string svg = line_chart_svg({{name, {1, 2}, {1, 2}, {}}}, o);
  EXPECT_EQ(svg.find(name), std::string::npos) << "one line of " << name.size() << " characters: " << svg;
  EXPECT_NE(svg.find("<tspan"), std::string::npos);
}

// Two points of one curve close in time and error (an NNAO ladder's cheapest rungs):
// their labels' boxes (10 px text, 5.6 px a character) do not overlap.
TEST(Chart, LabelsOfNearbyPointsDoNotOverlap) {
  ChartOptions o;
  o.log_x = true;
  const std::string a = "d4s4h4-quarter-b2-n0", b = "d8s4h8-quarter-b2-n0";
  const std::string svg = line_chart_svg({{"NNAO-exact", {0.40, 0.46, 10}, {0.0130, 0.0126, 0.0108}, {a, b, "full"}},
                                          {"SSAO", {0.47, 1.6}, {0.042, 0.036}, {"4", "32"}}},
                                         o);
  struct Text {
    double x, y;
    bool end;
  };
  auto find_text = [&](const std::string& label) {
    const size_t at = svg.find(">" + label + "<");
    EXPECT_NE(at, std::string::npos) << label;
    const size_t open = svg.rfind("<text", at);
    Text t{};
    std::sscanf(svg.c_str() + svg.find("x=\"", open) + 3, "%lf", &t.x);
    std::sscanf(svg.c_str() + svg.find("y=\"", open) + 3, "%lf", &t.y);
    t.end = svg.substr(open, at - open).find("text-anchor=\"end\"") != std::string::npos;
    return t;
  };
  const Text ta = find_text(a), tb = find_text(b);
  auto box = [](const Text& t, size_t chars, double& x0, double& x1) {
    const double w = 5.6 * double(chars);
    x0 = t.end ? t.x - w : t.x, x1 = t.end ? t.x : t.x + w;
  };
  double ax0, ax1, bx0, bx1;
  box(ta, a.size(), ax0, ax1), box(tb, b.size(), bx0, bx1);
  const bool x_overlap = ax0 < bx1 && bx0 < ax1, y_overlap = std::abs(ta.y - tb.y) < 11;
  EXPECT_FALSE(x_overlap && y_overlap) << "labels at (" << ta.x << ", " << ta.y << ") and (" << tb.x << ", " << tb.y
                                       << ")";
}
