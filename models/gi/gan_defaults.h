#pragma once
// train-gan's default model and schedule, chosen by the sweep (apps/sweep-gan.cpp,
// docs/gan.md "Model no more than a scene needs"): the smallest generator within 0.01
// SSIM of the best one swept, at the input size where that held, with as many epochs as
// fit the ~15 minute budget of the default run on 2 cores.
namespace nns::gi {

struct GanDefaults {
  int size = 32;    // face size: the global view is 128 x 64
  int ngf = 16;
  int ndf = 16;
  int levels = 5;
  int epochs = 20;
};

}  // namespace nns::gi
