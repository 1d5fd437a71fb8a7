#pragma once
// A model's linear light for one frame, as eval-gi scores it and gi-infer writes it: the
// network's prediction (gi_model_io.h), or with mirror averaging (test-time
// augmentation) the mean of it and the prediction for the mirrored frame (gi_augment.h),
// mirrored back. The mean is exactly mirror-equivariant (mirroring twice is the identity
// and float addition commutes), which the network alone is not; it costs the network
// twice. On the default data's validation scenes it lowered the MSE by 4-9% for each of
// three seeds (docs/results/2026-12-06-gi-averaging.md).
#include "models/gi/gi_model_io.h"
#include "runs/gi/gi_augment.h"

namespace nns::runs {

inline Tensor<float> model_light(gi::LoadedGenerator& g, const gi::GiSample& s, bool bn_batch_stats, bool dropout_on,
                                 bool mirror_average) {
  Tensor<float> p = gi::predict_linear(g, s, bn_batch_stats, dropout_on);
  if (!mirror_average) return p;
  gi::GiSample m_in;  // the network reads the input and the front rectangle alone
  m_in.name = s.name, m_in.input = mirrored_input(s), m_in.front = s.front;
  const Tensor<float> m = detail::flipped(gi::predict_linear(g, m_in, bn_batch_stats, dropout_on));
  for (int64_t i = 0; i < p.numel(); ++i) p[i] = 0.5f * (p[i] + m[i]);
  return p;
}

}  // namespace nns::runs
