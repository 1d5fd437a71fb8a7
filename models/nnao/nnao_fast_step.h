#pragma once
// The NNAO training step fused into one pass over plain arrays: dropout on the input,
// four Linear + PReLU-beta layers, MSE + gamma * sum|theta|, and the backward pass, with
// the gradients accumulated into the parameters' gradient buffers (the contract of
// core/autograd.h) for the project's Adam to apply.
//
// Why: the network is tiny (4 hidden units) and the step is ~0.5 M multiply-adds, so the
// general autograd path (one node, tensor and kernel call per op) spends most of its
// time on bookkeeping. The autograd path (NnaoNet::forward + nnao_loss + backward) stays
// the reference: tests compare the two on the same dropout mask.
//
// The step runs on the calling thread: ~20 us of work is less than what handing half
// of it to a second core costs. It uses the Dropout module's own Rng exactly as the
// module does (one 64-bit seed per step, core/kernels/dropout.h), so checkpoints and
// resumption behave the same with either path.
#include <cmath>
#include <stdexcept>
#include <vector>

#include "core/kernels/bf16.h"
#include "core/kernels/dropout.h"
#include "core/kernels/gemm_precision.h"
#include "models/nnao/nnao_model.h"

namespace nns::nnao {

class NnaoFastStep {
 public:
  NnaoFastStep(NnaoNet<float>& net, int batch) : net_(net), B_(batch), F_(net.config.inputs()), H_(net.config.hidden) {
    if (H_ > kMaxHidden || B_ < 1 || B_ > kMaxBatch)
      throw std::invalid_argument("NnaoFastStep: needs hidden <= 64 and 1 <= batch <= 256");
    xm_.resize(size_t(B_ * F_));
    mask_.resize(size_t(B_ * F_));
    for (auto& [name, r] : net.named_rngs())
      if (name == "drop.rng") rng_ = r;
    if (!rng_) throw std::logic_error("NnaoFastStep: the network has no dropout Rng 'drop.rng'");
    params_ = net.parameters();
  }

  // x: (B, F) standardised features, y: (B) standardised targets. Adds the gradients of
  // the loss to every parameter's gradient buffer and returns the loss.
  float forward_backward(const float* x, const float* y, float gamma) {
    const int64_t B = B_, F = F_;
    const int H = H_;
    // Dropout, exactly as the Dropout module draws it.
    const double p = net_.config.dropout;
    const float* xin = x;
    if (net_.is_training() && p > 0) {
      dropout_forward(xm_.data(), mask_.data(), x, B * F, p, rng_->next_u64());
      xin = xm_.data();
    }
    const float* W0 = net_.fc[0]->weight.value().data();
    // Precision::bf16 (gemm_precision.h): every operand of a matrix product is rounded to
    // bf16 (r), the sums stay fp32, as the GEMMs of the autograd path do in that mode.
    // The layer-0 operands are rounded once into copies; r is the identity in fp32.
    const bool bf16 = gemm_precision() == Precision::bf16;
    auto r = [bf16](float v) { return bf16 ? round_to_bf16(v) : v; };
    if (bf16) {
      xb_.resize(size_t(B * F));
      w0b_.resize(size_t(H * F));
      round_copy_bf16(xb_.data(), xin, 1, B * F, B * F);
      round_copy_bf16(w0b_.data(), W0, 1, H * F, H * F);
      xin = xb_.data();
      W0 = w0b_.data();
    }
    // Layer 0: z0[b][k] = b0[k] + x[b] . W0[k]; 16 independent partial sums per dot
    // product so the compiler vectorises without reassociating a float reduction.
    for (int64_t b = 0; b < B; ++b)
      for (int k = 0; k < H; ++k) {
        const float* xr = xin + b * F;
        const float* wr = W0 + int64_t(k) * F;
        float acc[16] = {};
        int64_t f = 0;
        for (; f + 16 <= F; f += 16)
          for (int l = 0; l < 16; ++l) acc[l] += xr[f + l] * wr[f + l];
        float s = 0;
        for (; f < F; ++f) s += xr[f] * wr[f];
        for (int l = 0; l < 16; ++l) s += acc[l];
        z_[0][b][k] = s + net_.fc[0]->bias.value()[k];
      }
    int width[5] = {int(F), H, H, H, 1};
    for (int l = 0; l < 4; ++l) {
      const float* al = net_.act[l]->alpha.value().data();
      const float* be = net_.act[l]->beta.value().data();
      if (l > 0) {
        const float* W = net_.fc[l]->weight.value().data();
        const float* bias = net_.fc[l]->bias.value().data();
        const int in = width[l], out = width[l + 1];
        for (int64_t b = 0; b < B; ++b)
          for (int o = 0; o < out; ++o) {
            float s = bias[o];
            for (int i = 0; i < in; ++i) s += r(W[o * in + i]) * r(a_[l - 1][b][i]);
            z_[l][b][o] = s;
          }
      }
      for (int64_t b = 0; b < B; ++b)
        for (int o = 0; o < width[l + 1]; ++o) {
          const float z = z_[l][b][o];
          a_[l][b][o] = z > 0 ? be[o] * z : al[o] * z;
        }
    }
    // MSE (mean over the batch) and its gradient.
    float loss = 0;
    for (int64_t b = 0; b < B; ++b) {
      const float d = a_[3][b][0] - y[b];
      loss += d * d;
      da_[b][0] = 2 * d / float(B);
    }
    loss /= float(B);
    // Backward through layers 3..0. da_ holds dLoss/d(a_l) for the current layer.
    for (int l = 3; l >= 0; --l) {
      const int in = width[l], out = width[l + 1];
      const float* al = net_.act[l]->alpha.value().data();
      const float* be = net_.act[l]->beta.value().data();
      float* dal = net_.act[l]->alpha.grad_buffer().data();
      float* dbe = net_.act[l]->beta.grad_buffer().data();
      for (int64_t b = 0; b < B; ++b)
        for (int o = 0; o < out; ++o) {
          const float z = z_[l][b][o], g = da_[b][o];
          if (z > 0) {
            dbe[o] += g * z;
            dz_[b][o] = g * be[o];
          } else {
            dal[o] += g * z;
            dz_[b][o] = g * al[o];
          }
        }
      float* dW = net_.fc[l]->weight.grad_buffer().data();
      float* db = net_.fc[l]->bias.grad_buffer().data();
      for (int64_t b = 0; b < B; ++b)
        for (int o = 0; o < out; ++o) db[o] += dz_[b][o];
      if (l == 0) {
        // dW0[k] += sum_b dz0[b][k] * x[b]: the one large product of the backward pass.
        for (int k = 0; k < H; ++k) {
          float* dwr = dW + int64_t(k) * F;
          for (int64_t b = 0; b < B; ++b) {
            const float c = r(dz_[b][k]);
            const float* xr = xin + b * F;
            for (int64_t f = 0; f < F; ++f) dwr[f] += c * xr[f];
          }
        }
        break;
      }
      const float* W = net_.fc[l]->weight.value().data();
      for (int64_t b = 0; b < B; ++b) {
        for (int i = 0; i < in; ++i) {
          float s = 0;
          for (int o = 0; o < out; ++o) s += r(dz_[b][o]) * r(W[o * in + i]);
          da_next_[b][i] = s;
        }
        for (int o = 0; o < out; ++o)
          for (int i = 0; i < in; ++i) dW[o * in + i] += r(dz_[b][o]) * r(a_[l - 1][b][i]);
      }
      for (int64_t b = 0; b < B; ++b)
        for (int i = 0; i < in; ++i) da_[b][i] = da_next_[b][i];
    }
    // gamma * sum|theta|: value and subgradient gamma * sign(theta) (0 at 0, as abs()).
    if (gamma != 0) {
      double l1 = 0;
      for (auto& prm : params_) {
        const float* w = prm.value().data();
        float* g = prm.grad_buffer().data();
        const int64_t n = prm.numel();
        float part = 0;
        for (int64_t i = 0; i < n; ++i) {
          part += std::abs(w[i]);
          g[i] += gamma * float((w[i] > 0) - (w[i] < 0));
        }
        l1 += part;
      }
      loss += gamma * float(l1);
    }
    return loss;
  }

 private:
  static constexpr int kMaxHidden = 64, kMaxBatch = 256;
  NnaoNet<float>& net_;
  int64_t B_, F_;
  int H_;
  Rng* rng_ = nullptr;
  std::vector<Var<float>> params_;
  std::vector<float> xm_, mask_;
  std::vector<float> xb_, w0b_;  // bf16-rounded layer-0 operands (Precision::bf16 only)
  // Per-layer activations for the batch (B <= kMaxBatch, widths <= kMaxHidden).
  struct Act {
    std::vector<float> v;
    int64_t stride = kMaxHidden;
    Act() : v(size_t(kMaxBatch * kMaxHidden)) {}
    float* operator[](int64_t b) { return v.data() + b * stride; }
  };
  Act z_[4], a_[4], dz_, da_, da_next_;
};

}  // namespace nns::nnao
