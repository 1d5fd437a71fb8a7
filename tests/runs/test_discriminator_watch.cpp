// The discriminator collapse watch (runs/gi/gan_trainer.h): a window of kWindow steps is
// a "D wins" window when D's mean loss is under kNearZero while G's adversarial loss
// climbs from the window before. train-gan's reaction to one (runs/gi/gan_run.h): a
// warning naming the step, and d_wins_windows / first_d_wins_step in summary.json and
// its last message; the run goes on (the L1 term still teaches the generator).
#include <gtest/gtest.h>

#include "runs/gi/gan_trainer.h"

using nns::runs::DiscriminatorWatch;

namespace {

// Feeds one window of constant losses; returns whether it closed as a "D wins" window.
bool window(DiscriminatorWatch& w, double d, double g_adv) {
  bool fired = false;
  for (int i = 0; i < DiscriminatorWatch::kWindow; ++i) {
    const bool f = w.add(d, g_adv);
    EXPECT_TRUE(!f || i + 1 == DiscriminatorWatch::kWindow) << "only a closing step can fire";
    fired |= f;
  }
  return fired;
}

}  // namespace

TEST(DiscriminatorWatch, FiresWhenDWinsAndGsAdversarialLossClimbs) {
  DiscriminatorWatch w;
  EXPECT_FALSE(window(w, 0.01, 2.0));  // the first window only sets the reference
  EXPECT_TRUE(window(w, 0.01, 3.0));   // D near 0, G's adversarial loss up
  EXPECT_TRUE(window(w, 0.02, 4.5));
  EXPECT_EQ(w.windows_won(), 2);
}

TEST(DiscriminatorWatch, HealthyOrRecoveringWindowsDoNotFire) {
  DiscriminatorWatch w;
  EXPECT_FALSE(window(w, 0.6, 0.8));
  EXPECT_FALSE(window(w, 0.6, 0.9));   // G's loss climbs, but D is not winning
  EXPECT_FALSE(window(w, 0.01, 0.7));  // D near 0, but G's loss falls
  EXPECT_FALSE(window(w, 0.2, 5.0));   // D above the threshold
  EXPECT_EQ(w.windows_won(), 0);
}

TEST(DiscriminatorWatch, SurvivesACheckpointMidWindow) {
  DiscriminatorWatch a, b;
  window(a, 0.01, 1.0);
  for (int i = 0; i < 40; ++i) a.add(0.01, 2.0);
  nns::Blob blob("checkpoint");
  a.save(blob);
  b.load(blob);
  bool fa = false, fb = false;
  for (int i = 40; i < DiscriminatorWatch::kWindow; ++i) fa |= a.add(0.01, 2.0), fb |= b.add(0.01, 2.0);
  EXPECT_TRUE(fa);
  EXPECT_EQ(fa, fb);
  EXPECT_EQ(a.windows_won(), b.windows_won());
}
