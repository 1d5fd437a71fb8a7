// dataset-info DIR: validates a G-buffer dataset (docs/dataset-format.md) and prints a
// summary. Exit code 0: clean; 1: problems found; 2: bad usage.
#include <cstdio>
#include <filesystem>

#include "apps/args.h"
#include "data/dataset.h"
#include "data/validate.h"
#include "runs/gi/gi_previews.h"

int main(int argc, char** argv) {
  nns::apps::Args args(argc, argv, "dataset-info",
                       "Validate a G-buffer EXR dataset and print views, resolutions, channels, "
                       "scenes, value ranges and every problem found.");
  std::string purpose = args.get_choice("--purpose", "any", {"any", "nnao", "gi"},
                                        "which trainer the data is for (decides required channels)");
  int max_problems = args.get_int("--max-problems", 50, "problems listed before '... and N more'", 0, 1000000);
  std::string sheet = args.get_string("--contact-sheet", "",
                                      "also write a PNG of the ground truth: albedo | shaded | "
                                      "indirect of each front view (GI data)");
  std::string sheet_split =
      args.get_choice("--sheet-split", "train", {nns::data::kSplitNames.begin(), nns::data::kSplitNames.end()},
                      "the split the sheet shows");
  std::string sheet_family = args.get_string("--sheet-family", "", "only frames of this scene family on the sheet");
  int sheet_frames = args.get_int("--sheet-frames", 12, "frames on the sheet", 1, 1000);
  int sheet_per_scene =
      args.get_int("--sheet-per-scene", 1, "frames of one scene on the sheet (a camera path's look alike)", 1, 1000);
  if (args.positional().size() > 1)
    args.error("expected one dataset folder, got " + std::to_string(args.positional().size()));
  args.done("DIR");
  if (args.positional().empty()) {
    std::fprintf(stderr, "dataset-info: error: missing the dataset folder\nrun 'dataset-info --help' for usage\n");
    return 2;
  }
  const std::string dir = args.positional()[0];
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    std::fprintf(stderr, "dataset-info: error: %s: not a folder\n", dir.c_str());
    return 2;
  }
  return nns::apps::run_main("dataset-info", [&] {
    nns::data::ValidateOptions o;
    o.purpose = purpose == "nnao" ? nns::data::Purpose::nnao
                : purpose == "gi" ? nns::data::Purpose::gi
                                  : nns::data::Purpose::any;
    o.max_problems = max_problems;
    auto report = nns::data::validate_dataset(dir, o);
    nns::data::print_report(stdout, report);
    if (!sheet.empty()) {
      auto listing = nns::data::list_dataset(dir);
      const auto& split = sheet_split == "train"  ? listing.train
                          : sheet_split == "test" ? listing.test
                                                  : listing.holdout;
      int n = nns::runs::write_contact_sheet(sheet, split, sheet_family, sheet_frames, sheet_per_scene);
      if (n == 0)
        throw std::runtime_error(dir + ": no " + sheet_split + " view or frame with indirect.*" +
                                 (sheet_family.empty() ? "" : " of family '" + sheet_family + "'") +
                                 " for --contact-sheet");
      std::printf("contact sheet: %s (%d %s frames; albedo | shaded | indirect)\n", sheet.c_str(), n,
                  sheet_split.c_str());
    }
    return report.clean() ? 0 : 1;
  });
}
