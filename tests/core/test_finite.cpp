#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "core/kernels/finite.h"
#include "core/thread_pool.h"

using namespace nns;

namespace {

template <class T>
void check_type() {
  const T bad[] = {std::numeric_limits<T>::infinity(), -std::numeric_limits<T>::infinity(),
                   std::numeric_limits<T>::quiet_NaN(), -std::numeric_limits<T>::quiet_NaN()};
  for (int threads : {1, 2}) {
    set_num_threads(threads);
    // Large enough to be split between threads and into several blocks.
    std::vector<T> v(300001);
    for (size_t i = 0; i < v.size(); ++i) v[i] = T(std::sin(double(i))) * T(1e30);
    v[7] = std::numeric_limits<T>::max();
    v[8] = -std::numeric_limits<T>::max();
    v[9] = std::numeric_limits<T>::denorm_min();
    EXPECT_TRUE(all_finite(v.data(), int64_t(v.size())));
    EXPECT_TRUE(all_finite(v.data(), 0));
    for (size_t at : {size_t(0), size_t(4095), size_t(150000), v.size() - 1})
      for (T b : bad) {
        const T keep = v[at];
        v[at] = b;
        EXPECT_FALSE(all_finite(v.data(), int64_t(v.size()))) << "at " << at << " threads " << threads;
        v[at] = keep;
      }
  }
}

TEST(AllFinite, Float) { check_type<float>(); }
TEST(AllFinite, Double) { check_type<double>(); }

}  // namespace
