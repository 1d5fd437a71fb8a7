#pragma once
// x^p by squaring (p >= 0), for a float or a 16-lane vector alike. NNAO's blur, the
// low-resolution upsample, the GLSL passes and the torch tool multiply in this order,
// so they agree to the bit; p = 8 is the ((x^2)^2)^2 the first NNAO models used.
namespace nns::screen_space {

template <class T>
T pow_by_squaring(T x, int p, T one) {
  T r = one;
  for (; p > 0; p >>= 1) {
    if (p & 1) r = r * x;
    if (p > 1) x = x * x;
  }
  return r;
}

}  // namespace nns::screen_space
