// The precision train-gan trains in when none is asked for (`--precision auto`): bf16 on
// an AMD CPU with AVX512-BF16, fp32 everywhere else, and the vendor as /proc/cpuinfo
// names it.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "core/kernels/gemm_precision.h"

using namespace nns;

TEST(GemmPrecision, AutoIsBf16OnlyOnAnAmdCpuWithAvx512Bf16) {
  CpuFeatures f;
  EXPECT_EQ(faster_training_precision(f), Precision::fp32) << "no AVX-512 at all";
  f.avx512f = f.avx512bw = f.avx512_bf16 = true;
  EXPECT_EQ(faster_training_precision(f), Precision::fp32) << "an Intel CPU with AVX512-BF16";
  f.amx_tile = f.amx_bf16 = true;
  EXPECT_EQ(faster_training_precision(f), Precision::fp32) << "an Intel CPU with AMX";
  f = CpuFeatures{};
  f.amd = true;
  EXPECT_EQ(faster_training_precision(f), Precision::fp32) << "an AMD CPU without AVX512-BF16 (Zen 3)";
  f.avx512f = f.avx512bw = f.avx512_bf16 = true;
  EXPECT_EQ(faster_training_precision(f), Precision::bf16) << "Zen 4, Zen 5";
}

TEST(GemmPrecision, AutoParsesToThisCpusChoice) {
  EXPECT_EQ(parse_precision("auto"), faster_training_precision(cpu_features()));
  EXPECT_EQ(parse_precision("fp32"), Precision::fp32);
  EXPECT_EQ(parse_precision("bf16"), Precision::bf16);
  EXPECT_THROW(parse_precision("fp16"), std::invalid_argument);
}

TEST(GemmPrecision, TheVendorIsTheOneProcCpuinfoNames) {
  std::ifstream in("/proc/cpuinfo");
  std::string line, vendor;
  while (vendor.empty() && std::getline(in, line))
    if (line.rfind("vendor_id", 0) == 0) vendor = line.substr(line.find(':') + 1);
  if (vendor.empty()) GTEST_SKIP() << "no vendor_id in /proc/cpuinfo";
  EXPECT_EQ(cpu_features().amd, vendor.find("AuthenticAMD") != std::string::npos) << vendor;
}
