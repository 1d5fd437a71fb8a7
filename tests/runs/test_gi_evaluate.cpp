// eval-gi sets aside frames with no light on their front geometry (nothing to predict;
// PSNR infinite for direct+env, a constant ambient loses there by construction).
#include <gtest/gtest.h>

#include "runs/gi/gi_evaluate.h"

using namespace nns;
using namespace nns::gi;

TEST(GiEvaluate, UnlitMeansNoLightOnGeometry) {
  GiSample s;
  s.target_linear = Tensor<float>({3, 2, 2});
  s.geometry = {1, 1, 0, 1};
  EXPECT_TRUE(unlit(s));
  s.target_linear[2] = 0.5f;  // channel R, pixel 2: sky, does not count
  EXPECT_TRUE(unlit(s));
  s.target_linear[2 * 4 + 3] = 1e-4f;  // channel B, pixel 3: geometry
  EXPECT_FALSE(unlit(s));
}
