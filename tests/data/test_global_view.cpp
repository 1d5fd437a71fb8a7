#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "data/coord_maps.h"
#include "data/global_view.h"
#include "report/image_write.h"
#include "support/image_bytes.h"
#include "render/surround.h"

using namespace nns;
using namespace nns::data;
using namespace nns::report;
using namespace nns::render;

namespace {

// Face f's pixel i holds f * 100000 + i: every source pixel is recognisable.
std::array<std::vector<float>, 6> tagged_faces(int F) {
  std::array<std::vector<float>, 6> faces;
  for (int f = 0; f < 6; ++f) {
    faces[size_t(f)].resize(size_t(F) * size_t(F));
    for (int i = 0; i < F * F; ++i) faces[size_t(f)][size_t(i)] = float(f * 100000 + i);
  }
  return faces;
}

std::vector<float> merged(const std::array<std::vector<float>, 6>& faces, int F) {
  std::array<const float*, 6> src;
  for (int f = 0; f < 6; ++f) src[size_t(f)] = faces[size_t(f)].data();
  std::vector<float> out(size_t(8) * size_t(F) * size_t(F));
  merge_to_global_view(src, F, out.data());
  return out;
}

float tag(Face f, int px, int py, int F) { return float(int(f) * 100000 + py * F + px); }

double angle(const std::array<float, 3>& a, const std::array<float, 3>& b) {
  double d = double(a[0]) * b[0] + double(a[1]) * b[1] + double(a[2]) * b[2];
  return std::acos(std::clamp(d, -1.0, 1.0));
}

}  // namespace

TEST(GlobalView, ThesisSizeAndFrontRect) {
  GlobalViewLayout L(256);
  EXPECT_EQ(L.width, 1024);
  EXPECT_EQ(L.height, 512);
  PixelRect r = L.front_rect();
  EXPECT_EQ(r.x0, 384);
  EXPECT_EQ(r.y0, 128);
  EXPECT_EQ(r.w, 256);
  EXPECT_EQ(r.h, 256);
  EXPECT_THROW(GlobalViewLayout(1), std::invalid_argument);
}

TEST(GlobalView, MiddleBandCopiesSideFacesWithBackSplitOverTheEdges) {
  for (int F : {8, 7}) {
    const int W = 4 * F, h = F / 2, T = F / 2;
    auto g = merged(tagged_faces(F), F);
    auto at = [&](int x, int y) { return g[size_t(y) * size_t(W) + size_t(x)]; };
    for (int py = 0; py < F; ++py)
      for (int px = 0; px < F; ++px) {
        EXPECT_EQ(at(2 * F - h + px, T + py), tag(Face::front, px, py, F));
        EXPECT_EQ(at(F - h + px, T + py), tag(Face::left, px, py, F));
        EXPECT_EQ(at(3 * F - h + px, T + py), tag(Face::right, px, py, F));
        // Back: its left columns on the right edge, its right columns on the left edge.
        int x = px < h ? 4 * F - h + px : px - h;
        EXPECT_EQ(at(x, T + py), tag(Face::back, px, py, F)) << "F=" << F << " px=" << px;
      }
  }
}

TEST(GlobalView, PolarBandsComeFromUpAndDownAndCoverThem) {
  const int F = 16, W = 64, T = 8;
  auto g = merged(tagged_faces(F), F);
  std::array<std::vector<int>, 6> seen;
  for (auto& s : seen) s.assign(size_t(F * F), 0);
  for (int y = 0; y < 2 * F; ++y)
    for (int x = 0; x < W; ++x) {
      int v = int(g[size_t(y * W + x)]);
      int f = v / 100000;
      if (y < T) EXPECT_EQ(f, int(Face::up));
      if (y >= T + F) EXPECT_EQ(f, int(Face::down));
      seen[size_t(f)][size_t(v % 100000)]++;
    }
  for (int f = 0; f < 6; ++f)
    for (int i = 0; i < F * F; ++i) EXPECT_GT(seen[size_t(f)][size_t(i)], 0) << "face " << f << " pixel " << i;
}

// The layout is right iff neighbouring global pixels look in neighbouring directions:
// a swapped or mirrored face edge shows up as a jump of ~90 degrees.
TEST(GlobalView, NeighboursInTheGlobalViewAreNeighboursOnTheSphere) {
  for (int F : {4, 7, 16, 32}) {
    GlobalViewLayout L(F);
    auto dir = [&](int x, int y) {
      int64_t i = int64_t(y) * L.width + x;
      int p = L.source_pixel(i);
      return face_direction(L.source_face(i), p % F, p / F, F);
    };
    // One face pixel spans at most 2/F radians; nearest sampling of the stretched
    // polar triangles moves a neighbour by up to ~1.4 face pixels more.
    const double bound = 4.0 / F;  // measured worst: 2.8 / F
    double worst = 0;
    for (int y = 0; y < L.height; ++y)
      for (int x = 0; x < L.width; ++x) {
        double right = angle(dir(x, y), dir((x + 1) % L.width, y));  // wraps: the panorama is periodic
        worst = std::max(worst, right);
        EXPECT_LT(right, bound) << "F=" << F << " x=" << x << " y=" << y;
        if (y + 1 < L.height) {
          double down = angle(dir(x, y), dir(x, y + 1));
          worst = std::max(worst, down);
          EXPECT_LT(down, bound) << "F=" << F << " x=" << x << " y=" << y << " (vertical)";
        }
      }
    RecordProperty("worst_neighbour_angle_F" + std::to_string(F), std::to_string(worst));
  }
}

TEST(GlobalView, ExtractFrontInvertsTheMerge) {
  const int F = 6;
  Tensor<float> g({2, 3, 2 * F, 4 * F});
  std::vector<std::array<std::vector<float>, 6>> all;
  for (int p = 0; p < 6; ++p) {
    auto faces = tagged_faces(F);
    for (auto& f : faces)
      for (auto& v : f) v += float(p) * 0.5f;
    auto m = merged(faces, F);
    std::copy(m.begin(), m.end(), g.data() + p * 8 * F * F);
    all.push_back(faces);
  }
  Tensor<float> front = extract_front(g);
  ASSERT_EQ(front.shape(), Shape({2, 3, F, F}));
  for (int p = 0; p < 6; ++p)
    for (int i = 0; i < F * F; ++i) EXPECT_EQ(front[p * F * F + i], all[size_t(p)][0][size_t(i)]);
  EXPECT_THROW(extract_front(Tensor<float>({1, 1, 4, 4})), std::invalid_argument);
}

// The mirror that train-gan's --aug-mirror relies on (runs/gi/gi_augment.h): for an
// even face size, the global view flipped left-right is the global view of the mirrored
// cube (every face flipped left-right, left and right swapped), pixel for pixel; for
// an odd size the front face is off centre and it is not.
TEST(GlobalView, FlippedGlobalViewIsTheMirroredCubeForEvenFaceSizes) {
  auto mirrored_source_matches = [](int F) {
    const GlobalViewLayout& L = global_view_layout(F);
    for (int y = 0; y < L.height; ++y)
      for (int x = 0; x < L.width; ++x) {
        const int64_t i = int64_t(y) * L.width + x, j = int64_t(y) * L.width + (L.width - 1 - x);
        Face f = L.source_face(i);
        Face m = f == Face::left ? Face::right : f == Face::right ? Face::left : f;
        const int p = L.source_pixel(i), flipped = (p / F) * F + (F - 1 - p % F);
        if (L.source_face(j) != m || L.source_pixel(j) != flipped) return false;
      }
    return true;
  };
  for (int F = 2; F <= 130; F += 2) EXPECT_TRUE(mirrored_source_matches(F)) << "face size " << F;
  for (int F : {3, 5, 33}) EXPECT_FALSE(mirrored_source_matches(F)) << "face size " << F;
}

TEST(CoordMaps, PhiThetaFollowTheDirections) {
  const int F = 16, W = 64, T = 8;
  auto m = phi_theta_maps(F);
  ASSERT_EQ(m.phi.size(), size_t(W * 2 * F));
  auto at = [&](const std::vector<float>& v, int x, int y) { return v[size_t(y * W + x)]; };
  // Straight ahead: the centre of the front rect.
  EXPECT_NEAR(at(m.phi, 2 * F, T + F / 2), 0.5, 0.02);
  EXPECT_NEAR(at(m.theta, 2 * F, T + F / 2), 0.5, 0.02);
  // Right face centre: phi 0.75; left: 0.25.
  EXPECT_NEAR(at(m.phi, 3 * F, T + F / 2), 0.75, 0.02);
  EXPECT_NEAR(at(m.phi, F, T + F / 2), 0.25, 0.02);
  // phi rises left to right along the horizon row; theta: pole rows near 0 and 1.
  for (int x = 1; x < W; ++x) EXPECT_GT(at(m.phi, x, T + F / 2), at(m.phi, x - 1, T + F / 2)) << x;
  for (int x = 0; x < W; ++x) {
    EXPECT_LT(at(m.theta, x, 0), 0.06) << x;
    EXPECT_GT(at(m.theta, x, 2 * F - 1), 0.94) << x;
  }
  for (float v : m.phi) EXPECT_TRUE(v >= 0 && v <= 1);
  for (float v : m.theta) EXPECT_TRUE(v >= 0 && v <= 1);
}

TEST(CoordMaps, XyAreNormalisedPixelCentres) {
  auto m = xy_coordinate_maps(4, 2);
  EXPECT_FLOAT_EQ(m.x[0], 0.125f);
  EXPECT_FLOAT_EQ(m.x[3], 0.875f);
  EXPECT_FLOAT_EQ(m.y[0], 0.25f);
  EXPECT_FLOAT_EQ(m.y[7], 0.75f);
}

// The picture in docs/global-view.md. Set NNSHADE_DOC_IMAGES=<folder> to regenerate it.
TEST(GlobalView, LayoutPicture) {
  const int F = 64;
  static const float colour[6][3] = {{0.9f, 0.9f, 0.9f}, {0.8f, 0.2f, 0.2f},  {0.2f, 0.6f, 0.9f},
                                     {0.3f, 0.8f, 0.3f}, {0.95f, 0.8f, 0.2f}, {0.6f, 0.3f, 0.8f}};
  std::array<std::array<std::vector<float>, 6>, 3> rgb;  // [channel][face]
  for (int c = 0; c < 3; ++c)
    for (int f = 0; f < 6; ++f) {
      auto& p = rgb[size_t(c)][size_t(f)];
      p.resize(size_t(F * F));
      for (int y = 0; y < F; ++y)
        for (int x = 0; x < F; ++x) {
          // Lighter towards each face's own image top; a grid every F/8 pixels; a dark
          // mark in the top-left corner shows the face's orientation.
          float shade = 0.45f + 0.55f * (1.0f - float(y) / F);
          if (x % (F / 8) == 0 || y % (F / 8) == 0) shade *= 0.6f;
          if (x < F / 8 && y < F / 8) shade = 0.1f;
          p[size_t(y * F + x)] = colour[f][c] * shade;
        }
    }
  std::vector<std::vector<float>> g(3);
  for (int c = 0; c < 3; ++c) g[size_t(c)] = merged(rgb[size_t(c)], F);
  const char* dir = std::getenv("NNSHADE_DOC_IMAGES");
  std::string path =
      dir ? std::string(dir) + "/global_view_layout.png"
          : (std::filesystem::temp_directory_path() / ("nns_global_view_" + std::to_string(getpid()) + ".png"))
                .string();
  write_png_rgb(path, g[0].data(), g[1].data(), g[2].data(), 4 * F, 2 * F, {.exposure = 1, .reinhard = false});
  int w = 0, h = 0;
  auto bytes = nns::testing::read_rgb8(path, &w, &h);
  EXPECT_EQ(w, 4 * F);
  EXPECT_EQ(h, 2 * F);
  // The front face's (white) colour sits in the middle of the image.
  size_t mid = (size_t(F) * size_t(w) + size_t(2 * F)) * 3;
  EXPECT_EQ(bytes[mid], bytes[mid + 1]);
  if (!dir) std::filesystem::remove(path);
}

// The renderer's cube cameras (render/surround.h) and face_direction() must agree,
// or the global view would stitch faces the renderer did not render that way.
TEST(GlobalView, FaceDirectionsMatchTheRenderersCubeCameras) {
  const int F = 8;
  Camera front = Camera::from_yaw_pitch({1, 2, 3}, 0.7f, -0.3f);
  auto cams = cube_face_cameras(front, F);
  for (int f = 0; f < 6; ++f)
    for (int py = 0; py < F; py += 3)
      for (int px = 0; px < F; px += 3) {
        float depth_per_t;
        Vec3 world = cams[size_t(f)].pixel_ray(px, py, depth_per_t);
        Vec3 in_front = cams[0].to_camera(world);
        auto mine = face_direction(Face(f), px, py, F);
        EXPECT_NEAR(in_front.x, mine[0], 1e-5) << kFaceNames[size_t(f)];
        EXPECT_NEAR(in_front.y, mine[1], 1e-5) << kFaceNames[size_t(f)];
        EXPECT_NEAR(in_front.z, mine[2], 1e-5) << kFaceNames[size_t(f)];
      }
}
