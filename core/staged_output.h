#pragma once
// A command's outputs appear together or not at all. An evaluation writes previews,
// tables, charts and a report one after the other; a run that failed between two of them
// (a full disk, a file-size limit) left the first ones in OUT — beside the files of an
// earlier run, or alone in a folder with no report. StagedOutput gives the run a folder of
// its own inside OUT, named like a temporary ("OUT/.stage.tmp.<pid>", so that
// remove_stale_temporaries clears one a killed run left); commit() moves each file to its
// place in OUT by rename(2), which replaces an earlier run's file of that name at once; a
// run that throws before commit() leaves OUT as it was.
//
//   FolderLock lock = prepare_output_folder(out, "eval-gi");
//   StagedOutput stage(out);
//   o.out = stage.dir();      // everything is written here
//   run(o);
//   stage.commit();           // and appears in `out` now
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/atomic_file.h"

namespace nns {

class StagedOutput {
 public:
  // `out` must exist and be locked by this run (core/folder_lock.h).
  explicit StagedOutput(const std::string& out)
      : out_(out), dir_((std::filesystem::path(out) / (".stage" + detail::temp_name(""))).string()) {
    std::filesystem::create_directories(dir_);
  }
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;
  ~StagedOutput() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);  // nothing left after commit(); everything after a failure
  }

  const std::string& dir() const { return dir_; }

  // Moves every file of the stage to the same path under `out`, making the folders it
  // needs; a folder of an earlier run (previews/) keeps its other files. Throws naming
  // the file that could not be moved.
  void commit() {
    namespace fs = std::filesystem;
    std::vector<fs::path> files;  // relative to the stage
    for (auto it = fs::recursive_directory_iterator(dir_); it != fs::recursive_directory_iterator(); ++it)
      if (!it->is_directory()) files.push_back(fs::relative(it->path(), dir_));
    for (const fs::path& rel : files) {
      const fs::path to = fs::path(out_) / rel;
      fs::create_directories(to.parent_path());
      detail::rename_into_place((fs::path(dir_) / rel).string(), to.string());
    }
    std::error_code ec;
    fs::remove_all(dir_, ec);  // empty folders only, now
  }

 private:
  std::string out_, dir_;
};

}  // namespace nns
