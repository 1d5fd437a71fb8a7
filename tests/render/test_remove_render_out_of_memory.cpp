// render::remove_render runs while a failed render's error is on its way out and is
// noexcept: an allocation that fails inside it (it lists the folder's views) must come
// back as "could not remove", not end the process in std::terminate.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <new>
#include <string>

#include "render/dataset_writer.h"

namespace {
bool g_refuse_allocations = false;
}

// Every allocation of this test binary goes through here; while g_refuse_allocations is
// set, each one fails as it would with the memory exhausted.
void* operator new(std::size_t n) {
  if (g_refuse_allocations) throw std::bad_alloc();
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace fs = std::filesystem;

TEST(RemoveRender, AnAllocationThatFailsIsReportedNotFatal) {
  const fs::path d = fs::temp_directory_path() / ("nns_remove_render_oom_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d / "train");
  std::ofstream(d / "a-v000.exr") << "x";
  std::ofstream(d / "train" / "b-v000.exr") << "x";
  const std::string out = d.string();
  g_refuse_allocations = true;
  const bool removed = nns::render::remove_render(out);
  g_refuse_allocations = false;
  EXPECT_FALSE(removed) << "nothing could be listed, so not everything was removed";
  EXPECT_TRUE(nns::render::remove_render(out)) << "with memory again, the render goes";
  EXPECT_FALSE(fs::exists(d / "train"));
  EXPECT_FALSE(fs::exists(d / "a-v000.exr"));
  fs::remove_all(d);
}
