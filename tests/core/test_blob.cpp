#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/blob.h"

using namespace nns;
namespace fs = std::filesystem;

namespace {

// A fresh folder per test, removed afterwards.
class BlobTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nns_blob_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

Blob sample() {
  Blob b("test-model");
  b.set_config("hidden", 16);
  b.set_config("lr", 2e-4);
  b.set_config("activation", "prelu");
  b.put("fc.weight", Tensor<float>::from({2, 3}, {1, -2, 3.5f, 0, 1e-30f, -0.0f}));
  b.put("fc.bias", Tensor<double>::from({3}, {0.1, -0.2, 1e300}));
  const uint64_t state[4] = {1, 0xFFFFFFFFFFFFFFFFull, 42, 7};
  b.put("rng", Shape{4}, state);
  b.put_i64("step", -3);
  b.put("empty", Tensor<float>::zeros({0, 5}));
  b.put("scalar", Tensor<float>::from(Shape{}, {2.5f}));
  return b;
}

std::string slurp(const std::string& p) { return read_file(p); }
void spit(const std::string& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
}

// Expects loading `p` to throw a runtime_error whose message names the file and has `what`.
void expect_load_error(const std::string& p, const std::string& what) {
  try {
    Blob::load(p);
    ADD_FAILURE() << "loading " << p << " did not throw (expected '" << what << "')";
  } catch (const std::runtime_error& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find(p), std::string::npos) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  }
}

}  // namespace

TEST(Crc32, MatchesTheStandardCheckValue) {
  EXPECT_EQ(crc32("123456789", 9), 0xCBF43926u);
  EXPECT_EQ(crc32("", 0), 0u);
}

TEST_F(BlobTest, RoundTripIsBitwise) {
  Blob b = sample();
  b.save(path("a.blob"));
  Blob r = Blob::load(path("a.blob"));
  EXPECT_EQ(r.kind(), "test-model");
  EXPECT_EQ(r.config_int("hidden"), 16);
  EXPECT_EQ(r.config_double("lr"), 2e-4);
  EXPECT_EQ(r.config_string("activation"), "prelu");
  auto w = r.tensor<float>("fc.weight", {2, 3});
  EXPECT_EQ(w[1], -2.0f);
  EXPECT_EQ(w[4], 1e-30f);
  EXPECT_TRUE(std::signbit(w[5]));
  EXPECT_EQ(r.tensor<double>("fc.bias", {3})[2], 1e300);
  uint64_t s[4];
  r.read("rng", {4}, s);
  EXPECT_EQ(s[1], 0xFFFFFFFFFFFFFFFFull);
  EXPECT_EQ(r.get_i64("step"), -3);
  EXPECT_EQ(r.at("empty").numel(), 0);
  EXPECT_EQ(r.tensor<float>("scalar", Shape{})[0], 2.5f);
  // Save what was loaded: identical bytes.
  r.save(path("b.blob"));
  EXPECT_EQ(slurp(path("a.blob")), slurp(path("b.blob")));
  EXPECT_EQ(slurp(path("a.blob")), b.serialize());
}

TEST_F(BlobTest, TensorDataIsAlignedTo64Bytes) {
  std::string bytes = sample().serialize();
  // Each tensor's data follows its header; find the f64 1e300 and check its offset.
  double big = 1e300;
  auto pos = bytes.find(std::string(reinterpret_cast<const char*>(&big), 8));
  ASSERT_NE(pos, std::string::npos);
  EXPECT_EQ((pos - 16) % 64, 0u);  // 1e300 is the third double of fc.bias
}

TEST_F(BlobTest, WritesLeaveNoTemporaryFiles) {
  sample().save(path("a.blob"));
  sample().save(path("a.blob"));  // overwrite
  int files = 0;
  for (auto& e : fs::directory_iterator(dir_)) {
    ++files;
    EXPECT_EQ(e.path().filename(), "a.blob");
  }
  EXPECT_EQ(files, 1);
}

TEST_F(BlobTest, UnwritableFolderNamesThePath) {
  std::string p = path("no/such/folder/a.blob");
  try {
    sample().save(p);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
  }
}

TEST_F(BlobTest, MissingFileNamesThePath) { expect_load_error(path("absent.blob"), "cannot open"); }

// A folder given as --model failed with "basic_filebuf::underflow ... Is a
// directory", naming no path.
TEST_F(BlobTest, AFolderNamesThePath) {
  fs::create_directories(path("model.blob"));
  expect_load_error(path("model.blob"), "is a folder");
  try {
    read_file(path("model.blob"));
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path("model.blob")), std::string::npos) << e.what();
  }
}

TEST_F(BlobTest, TruncatedFilesAreReported) {
  std::string bytes = sample().serialize();
  for (size_t n : {size_t(0), size_t(5), size_t(20), size_t(40), bytes.size() / 2, bytes.size() - 1}) {
    spit(path("t.blob"), bytes.substr(0, n));
    SCOPED_TRACE("length " + std::to_string(n));
    expect_load_error(path("t.blob"), "truncated");
  }
}

TEST_F(BlobTest, CorruptBytesFailTheChecksum) {
  std::string bytes = sample().serialize();
  for (size_t at : {size_t(30), bytes.size() / 2, bytes.size() - 5, bytes.size() - 1}) {
    std::string bad = bytes;
    bad[at] ^= 0x10;
    spit(path("c.blob"), bad);
    SCOPED_TRACE("byte " + std::to_string(at));
    expect_load_error(path("c.blob"), "checksum mismatch");
  }
}

TEST_F(BlobTest, WrongMagicIsReported) {
  std::string bytes = sample().serialize();
  bytes[0] = 'X';
  spit(path("m.blob"), bytes);
  expect_load_error(path("m.blob"), "bad magic");
  spit(path("text.blob"), "hello, this is not a blob at all");
  expect_load_error(path("text.blob"), "bad magic");
}

TEST_F(BlobTest, WrongVersionIsReported) {
  std::string bytes = sample().serialize();
  bytes[8] = 2;
  spit(path("v.blob"), bytes);
  expect_load_error(path("v.blob"), "format version 2 is not supported");
}

TEST_F(BlobTest, TrailingBytesAreReported) {
  spit(path("x.blob"), sample().serialize() + "junk");
  expect_load_error(path("x.blob"), "unexpected bytes");
}

TEST_F(BlobTest, ShapeMismatchNamesTheTensorAndFile) {
  sample().save(path("s.blob"));
  Blob r = Blob::load(path("s.blob"));
  try {
    r.tensor<float>("fc.weight", {3, 2});
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find(path("s.blob")), std::string::npos) << msg;
    EXPECT_NE(msg.find("'fc.weight' has shape [2,3], expected [3,2]"), std::string::npos) << msg;
  }
}

TEST_F(BlobTest, MissingTensorAndWrongDtypeAreNamed) {
  Blob b = sample();
  try {
    b.tensor<float>("fc.wieght", {2, 3});
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'fc.wieght' is missing"), std::string::npos) << e.what();
  }
  try {
    b.tensor<float>("rng", {4});
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("dtype u64, expected f32"), std::string::npos) << e.what();
  }
}

TEST_F(BlobTest, FloatTensorsConvertBetweenPrecisions) {
  Blob b = sample();
  auto w = b.tensor<double>("fc.weight", {2, 3});
  EXPECT_EQ(w[2], 3.5);
  Blob small;
  small.put("bias", Tensor<double>::from({2}, {0.1, -0.2}));
  EXPECT_EQ(small.tensor<float>("bias", {2})[0], 0.1f);
  // 1e300 does not fit a float: read as one it would be an infinite weight.
  try {
    b.tensor<float>("fc.bias", {3});
    ADD_FAILURE() << "1e300 read as a float";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("tensor 'fc.bias' holds a non-finite value (Inf) at index 2"),
              std::string::npos)
        << e.what();
  }
}

// A CRC-valid blob with a NaN or inf weight was used: nnao-infer gave AO = 0 on every
// pixel and exited 0. Every floating-point read refuses it, naming the file and tensor.
TEST_F(BlobTest, ANonFiniteValueIsRefusedNamingTheFileTheTensorAndTheIndex) {
  for (float bad : {std::nanf(""), HUGE_VALF, -HUGE_VALF}) {
    Blob b("nnao");
    b.put("fc1.weight", Tensor<float>::from({2, 2}, {1, 2, bad, 4}));
    b.put("stats", Tensor<double>::from({2}, {0.5, double(bad)}));
    b.save(path("nnao.blob"));
    const Blob r = Blob::load(path("nnao.blob"));
    for (auto [name, index] : {std::pair<const char*, int>{"fc1.weight", 2}, {"stats", 1}}) {
      for (int as_double = 0; as_double < 2; ++as_double) {
        try {
          const Shape shape = std::string(name) == "stats" ? Shape{2} : Shape{2, 2};
          if (as_double) r.tensor<double>(name, shape);
          else r.tensor<float>(name, shape);
          ADD_FAILURE() << name << " " << bad << " accepted";
        } catch (const std::runtime_error& e) {
          const std::string m = e.what();
          EXPECT_NE(m.find(path("nnao.blob")), std::string::npos) << m;
          EXPECT_NE(m.find(std::string("tensor '") + name + "' holds a non-finite value (" +
                           (std::isnan(bad) ? "NaN" : "Inf") + ") at index " + std::to_string(index)),
                    std::string::npos)
              << m;
        }
      }
    }
  }
}

// A radius of 1e39 passed as a double and became inf as a float; a window of 4294967303
// was narrowed to 7 before any check.
TEST_F(BlobTest, ConfigNumbersAreFiniteAsFloatsAndIntegersCheckedAsStored) {
  Blob b("nnao");
  for (const char* bad : {"1e39", "nan", "inf", "-inf", "1e309"}) {
    b.set_config("radius", std::string(bad));
    EXPECT_THROW(b.config_double("radius"), std::runtime_error) << bad;
  }
  b.set_config("radius", 1e38);
  EXPECT_EQ(b.config_double("radius"), 1e38);
  b.set_config("window", std::string("4294967303"));
  try {
    b.config_int("window", 1, 63);
    ADD_FAILURE() << "4294967303 accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("config key 'window' is 4294967303, out of range 1..63"), std::string::npos)
        << e.what();
  }
  b.set_config("window", 7);
  EXPECT_EQ(b.config_int("window", 1, 63), 7);
}

TEST_F(BlobTest, DuplicateNamesAreRejected) {
  Blob b;
  b.put_i64("a", 1);
  EXPECT_THROW(b.put_i64("a", 2), std::runtime_error);
}

TEST_F(BlobTest, ConfigErrorsNameTheKey) {
  Blob b = sample();
  EXPECT_THROW(b.config_string("nope"), std::runtime_error);
  try {
    b.config_int("activation");
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'activation' is 'prelu', not an integer"), std::string::npos);
  }
}

// Writes sample() for tests/tools/test_read_blob.py, which runs this test with
// NNS_BLOB_SAMPLE_OUT set and checks that numpy reads the same values.
TEST(BlobSample, WriteForPythonReader) {
  const char* out = std::getenv("NNS_BLOB_SAMPLE_OUT");
  std::string p = out ? out : "/tmp/nns_blob_sample_" + std::to_string(::getpid()) + ".blob";
  sample().save(p);
  EXPECT_EQ(read_file(p), sample().serialize());
  if (!out) std::remove(p.c_str());
}
