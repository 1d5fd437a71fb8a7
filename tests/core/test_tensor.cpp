#include <gtest/gtest.h>

#include <cstdint>

#include "core/allocator.h"
#include "core/tensor.h"

using namespace nns;

TEST(Shape, BasicsAndLimits) {
  Shape s{2, 3, 4};
  EXPECT_EQ(s.dim(), 3);
  EXPECT_EQ(s.numel(), 24);
  EXPECT_EQ(s[-1], 4);
  EXPECT_EQ(s.str(), "[2,3,4]");
  EXPECT_EQ(Shape{}.numel(), 1);  // a scalar
  EXPECT_EQ((Shape{3, 0}).numel(), 0);
  EXPECT_NE((Shape{2, 3}), (Shape{3, 2}));
  EXPECT_THROW((Shape{1, 2, 3, 4, 5, 6, 7}), std::invalid_argument);
  EXPECT_THROW((Shape{2, -1}), std::invalid_argument);
}

TEST(Tensor, FactoriesFillValues) {
  auto z = Tensor<float>::zeros({2, 3});
  auto o = Tensor<double>::ones({4});
  auto f = Tensor<float>::full({3}, 2.5f);
  for (float v : z) EXPECT_EQ(v, 0.0f);
  for (double v : o) EXPECT_EQ(v, 1.0);
  for (float v : f) EXPECT_EQ(v, 2.5f);
  auto t = Tensor<float>::from({2, 2}, {1, 2, 3, 4});
  EXPECT_EQ(t[3], 4.0f);
  EXPECT_EQ(t.size(0), 2);
  EXPECT_THROW(Tensor<float>::from({2, 2}, {1, 2, 3}), std::invalid_argument);
  EXPECT_FALSE(Tensor<float>().defined());
}

TEST(Tensor, CopiesShareStorageClonesDoNot) {
  auto a = Tensor<float>::zeros({3});
  Tensor<float> b = a;
  Tensor<float> c = a.clone();
  b[0] = 5;
  EXPECT_EQ(a[0], 5.0f);
  EXPECT_EQ(c[0], 0.0f);
  EXPECT_TRUE(a.shares_storage(b));
  EXPECT_FALSE(a.shares_storage(c));
}

TEST(Tensor, ReshapeIsAViewOfTheSameSize) {
  auto a = Tensor<float>::from({2, 3}, {0, 1, 2, 3, 4, 5});
  auto r = a.reshape({3, 2});
  EXPECT_TRUE(r.shares_storage(a));
  EXPECT_EQ(r.shape(), (Shape{3, 2}));
  r[5] = 9;
  EXPECT_EQ(a[5], 9.0f);
  EXPECT_THROW(a.reshape({4, 2}), std::invalid_argument);
}

TEST(Tensor, CastConvertsEachElement) {
  auto a = Tensor<double>::from({2}, {1.5, -2.25});
  auto f = a.cast<float>();
  EXPECT_EQ(f[0], 1.5f);
  EXPECT_EQ(f[1], -2.25f);
}

TEST(Tensor, CheckShapeNamesWhatAndBothShapes) {
  auto a = Tensor<float>::zeros({2, 3});
  try {
    check_shape(a, {3, 2}, "conv weight");
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "conv weight: expected shape [3,2], got [2,3]");
  }
}

TEST(Allocator, StorageIsAlignedAndReusedAfterRelease) {
  const float* first;
  {
    Tensor<float> t({1000, 37});
    first = t.data();
    EXPECT_EQ(reinterpret_cast<uintptr_t>(first) % 64, 0u);
  }
  // The same size class comes back from the cache, not from malloc.
  Tensor<float> u({1000, 37});
  EXPECT_EQ(u.data(), first);
  EXPECT_EQ(CachingAllocator::size_class(100), 128u);
  EXPECT_EQ(CachingAllocator::size_class(5000), 5120u);  // 8192 / 8 steps
}
