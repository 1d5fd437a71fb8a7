#include <gtest/gtest.h>

#include <cmath>

#include "data/augment.h"

using namespace nns;
using namespace nns::data;

namespace {

// A 5x3 view with distinct values everywhere and a normal that points right-and-up.
View sample(int w = 5, int h = 3) {
  View v;
  v.width = w;
  v.height = h;
  v.fov_y_deg = 40;
  v.scene = "s";
  for (const char* c : {"Z", "N.X", "N.Y", "N.Z", "AO"}) v.add_channel(c);
  for (int i = 0; i < w * h; ++i) {
    v.channels["Z"][size_t(i)] = 1 + float(i);
    v.channels["AO"][size_t(i)] = float(i) / float(w * h);
    v.channels["N.X"][size_t(i)] = 0.6f;
    v.channels["N.Y"][size_t(i)] = 0.0f + 0.01f * float(i);
    v.channels["N.Z"][size_t(i)] = 0.8f;
  }
  v.world_to_camera = std::array<float, 16>{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 0, 0, 0, 1};
  return v;
}

}  // namespace

TEST(Augment, FourQuarterTurnsAreTheIdentity) {
  View v = sample();
  View r = v;
  for (int k = 0; k < 4; ++k) {
    r = transform_view(r, {1, false});
    if (k < 3) EXPECT_NE(r.channels, v.channels);
  }
  EXPECT_EQ(r.width, v.width);
  EXPECT_EQ(r.channels, v.channels);
  EXPECT_NEAR(r.fov_y_deg, v.fov_y_deg, 1e-4);
  for (size_t i = 0; i < 16; ++i) EXPECT_FLOAT_EQ((*r.world_to_camera)[i], (*v.world_to_camera)[i]);
}

TEST(Augment, MirrorNegatesNormalXAndMovesPixels) {
  View v = sample();
  View m = transform_view(v, {0, true});
  for (int y = 0; y < v.height; ++y)
    for (int x = 0; x < v.width; ++x) {
      EXPECT_EQ(m.at("N.X", v.width - 1 - x, y), -v.at("N.X", x, y));
      EXPECT_EQ(m.at("N.Y", v.width - 1 - x, y), v.at("N.Y", x, y));
      EXPECT_EQ(m.at("Z", v.width - 1 - x, y), v.at("Z", x, y));
    }
  EXPECT_EQ(transform_view(m, {0, true}).channels, v.channels);
}

TEST(Augment, QuarterTurnTurnsTheNormalWithThePicture) {
  View v = sample(5, 3);
  View r = transform_view(v, {1, false});
  ASSERT_EQ(r.width, 3);
  ASSERT_EQ(r.height, 5);
  // Counter-clockwise: the top-right pixel becomes the top-left one.
  EXPECT_EQ(r.at("Z", 0, 0), v.at("Z", 4, 0));
  EXPECT_EQ(r.at("Z", 2, 4), v.at("Z", 0, 2));
  // A normal pointing right (+x) now points up (+y): (x, y) -> (-y, x).
  EXPECT_FLOAT_EQ(r.at("N.X", 0, 0), -v.at("N.Y", 4, 0));
  EXPECT_FLOAT_EQ(r.at("N.Y", 0, 0), v.at("N.X", 4, 0));
  EXPECT_EQ(r.at("N.Z", 0, 0), v.at("N.Z", 4, 0));
  // The old horizontal field of view is the new vertical one.
  double fovx = 2 * std::atan(std::tan(40 * M_PI / 360) * 5.0 / 3.0) * 180 / M_PI;
  EXPECT_NEAR(r.fov_y_deg, fovx, 1e-4);
}

TEST(Augment, AllEightSymmetriesAreDistinctAndRandomCoversThem) {
  View v = sample(4, 4);
  std::vector<std::map<std::string, std::vector<float>>> seen;
  for (int k = 0; k < 4; ++k)
    for (bool m : {false, true}) {
      auto c = transform_view(v, {k, m}).channels;
      for (auto& s : seen) EXPECT_NE(s, c) << k << m;
      seen.push_back(c);
    }
  Rng rng(3);
  int counts[8] = {};
  for (int i = 0; i < 800; ++i) {
    Dihedral d = Dihedral::random(rng);
    counts[d.quarter_turns + 4 * d.mirror]++;
  }
  for (int c : counts) EXPECT_GT(c, 60);
}

TEST(Augment, TransformPlanesNeedsBothNormalComponents) {
  std::vector<float> src(4), dst(4);
  EXPECT_THROW(transform_planes({"N.X"}, src.data(), 2, 2, {1, false}, dst.data()), std::invalid_argument);
  EXPECT_NO_THROW(transform_planes({"AO"}, src.data(), 2, 2, {1, false}, dst.data()));
}
