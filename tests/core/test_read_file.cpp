#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <string>

#include "core/atomic_file.h"
#include "core/blob.h"

using namespace nns;
namespace fs = std::filesystem;

namespace {

class ReadFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nns_read_file_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

// The message of what `read` throws, or "" when it returns.
template <class F>
std::string error_of(F&& read) {
  try {
    read();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// A FIFO as a model or checkpoint blocked the reader forever, waiting for a writer.
TEST_F(ReadFileTest, AFifoIsRefusedAtOnceNamingTheFile) {
  const std::string p = path("checkpoint.blob");
  ASSERT_EQ(::mkfifo(p.c_str(), 0600), 0);
  auto read = std::async(std::launch::async, [&] { return error_of([&] { Blob::load(p); }); });
  if (read.wait_for(std::chrono::seconds(5)) != std::future_status::ready) {
    ADD_FAILURE() << "reading a FIFO blocks";
    int fd = ::open(p.c_str(), O_WRONLY);  // lets the blocked reader go on
    if (fd >= 0) ::close(fd);
  }
  const std::string e = read.get();
  EXPECT_NE(e.find(p), std::string::npos) << e;
  EXPECT_NE(e.find("FIFO"), std::string::npos) << e;
  EXPECT_NE(e.find("regular file"), std::string::npos) << e;
}

// /dev/zero as --model allocated until memory ran out; a device is no file to read.
TEST_F(ReadFileTest, ADeviceIsRefusedEvenThroughASymlink) {
  const std::string link = path("nnao.blob");
  fs::create_symlink("/dev/null", link);
  for (const std::string& p : {std::string("/dev/null"), link}) {
    const std::string e = error_of([&] { read_file(p); });
    EXPECT_NE(e.find(p), std::string::npos) << e;
    EXPECT_NE(e.find("character device"), std::string::npos) << e;
    EXPECT_NE(e.find("4 GiB"), std::string::npos) << "the limit is stated: " << e;
  }
}

TEST_F(ReadFileTest, AFileAboveTheLimitIsRefusedStatingTheLimit) {
  const std::string p = path("params.txt");
  std::ofstream(p) << std::string(2048, 'x');
  EXPECT_EQ(read_file(p, 2048).size(), 2048u);
  const std::string e = error_of([&] { read_file(p, 1024); });
  EXPECT_NE(e.find(p), std::string::npos) << e;
  EXPECT_NE(e.find("2048 bytes, more than the limit of 1 KiB"), std::string::npos) << e;
}

TEST_F(ReadFileTest, ReadsARegularFileWhole) {
  const std::string p = path("a.txt");
  std::string bytes;
  for (int i = 0; i < 100000; ++i) bytes += char('a' + i % 26);
  std::ofstream(p, std::ios::binary) << bytes;
  EXPECT_EQ(read_file(p), bytes);
  std::ofstream(path("empty"), std::ios::binary);
  EXPECT_EQ(read_file(path("empty")), "");
  EXPECT_NE(error_of([&] { read_file(path("absent")); }).find("cannot open"), std::string::npos);
}

}  // namespace
