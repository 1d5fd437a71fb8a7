// report.html of every kind of run — eval-ao, train-nnao, train-gan, eval-gi — opened in
// headless Chromium at 1280 px as a person would open it: every image loads (even from a
// folder whose name holds markup, '#', '%' and quotes), the page is not blank, each image
// comparison flips with its radio buttons (CSS only), nothing a file name carries
// becomes markup, no table cell reads "nan", and no text of a chart (legend, axis label,
// tick) runs off its image. The page itself has no script: the image check runs in a copy of it
// with one script appended.
//
// Chromium is Debian's `chromium` (scripts/install-deps); without it these tests fail,
// saying so, rather than skip.
#include <gtest/gtest.h>

#include <unistd.h>

#include <array>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include "core/atomic_file.h"
#include "data/exr_io.h"
#include "fixtures/synthetic_gbuffer.h"
#include "report/image_write.h"
#include "support/image_bytes.h"
#include "tests/support/run_command.h"
#include "tests/support/synthetic_gi_dataset.h"

namespace fs = std::filesystem;
using nns::testing::CommandResult;
using nns::testing::run_app;
using nns::testing::run_command;

namespace {

// Markup, a URL fragment and query, a percent sign and quotes (no '/': one folder): a
// preview's file name begins with the data folder's name, so the page must escape it
// as text and encode it as a URL.
const std::string kOddFolder = "views #1 & <i> \"50%\" ?q";

// A path as one shell word (the test's own names hold no single quote).
std::string shell_arg(const fs::path& p) { return "'" + p.string() + "'"; }

// Run in a copy of the page: which images failed to load, whether the k-th radio button
// of each comparison shows the k-th image only, and whether any <i> element (from the
// odd folder name) exists.
const char* kCheckScript = R"(<script>
addEventListener('load', () => {
  const failed = [];
  for (const im of document.images) if (!(im.complete && im.naturalWidth > 0)) failed.push(im.getAttribute('src'));
  let flip = 'ok';
  for (const c of document.querySelectorAll('.cmp')) {
    const inputs = c.querySelectorAll(':scope > input'), figures = c.querySelectorAll('.stage > figure');
    if (inputs.length !== figures.length || inputs.length < 2) flip = inputs.length + ' buttons, ' + figures.length + ' images';
    inputs.forEach((input, k) => {
      input.checked = true;
      figures.forEach((f, j) => {
        if ((getComputedStyle(f).display !== 'none') !== (j === k)) flip = 'button ' + k + ' and image ' + j;
      });
    });
  }
  const nan = [...document.querySelectorAll('td, th')].filter(c => /^\s*[-+]?nan\s*$/i.test(c.textContent)).length;
  const p = document.createElement('pre');
  p.id = 'nns-check';
  p.textContent = 'images=' + document.images.length + ' comparisons=' + document.querySelectorAll('.cmp').length +
      ' injected=' + document.querySelectorAll('i').length + ' flip=' + flip + ' nan_cells=' + nan +
      ' failed=' + JSON.stringify(failed);
  document.body.appendChild(p);
});
</script>)";

// Run in a page that holds a run's charts inline (the report shows them as images, whose
// insides a script cannot measure): every text of every chart must lie inside its chart.
const char* kChartScript = R"(<script>
addEventListener('load', () => {
  const cut = [];
  for (const svg of document.querySelectorAll('svg')) {
    const box = svg.getBoundingClientRect();
    for (const t of svg.querySelectorAll('text')) {
      const r = t.getBoundingClientRect();
      if (r.left < box.left - 0.5 || r.right > box.right + 0.5 || r.top < box.top - 0.5 || r.bottom > box.bottom + 0.5)
        cut.push(t.textContent);
    }
  }
  const p = document.createElement('pre');
  p.id = 'nns-charts';
  p.textContent = 'charts=' + document.querySelectorAll('svg').length + ' cut=' + JSON.stringify(cut);
  document.body.appendChild(p);
});
</script>)";

class ReportHtml : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = fs::temp_directory_path() / ("nns_report_html_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  void SetUp() override { ASSERT_FALSE(chromium().empty()); }  // before the runs: fail fast, saying why

  // chromium's path; fails the test (not a skip) when it is missing.
  static std::string chromium() {
    const CommandResult r = run_command("command -v chromium || command -v chromium-browser");
    std::string path = r.output.substr(0, r.output.find('\n'));
    EXPECT_EQ(r.code, 0) << "chromium is not installed: run scripts/install-deps (Debian package chromium); "
                            "the report.html tests open the pages in headless Chromium";
    return r.code == 0 ? path : "";
  }

  static std::string headless(const std::string& flags, const fs::path& page) {
    const fs::path profile = root_ / "chromium-profile";
    const CommandResult r = run_command("timeout 120 " + chromium() + " --headless --no-sandbox --disable-gpu " +
                                        "--hide-scrollbars --user-data-dir=" + shell_arg(profile) + " " + flags + " " +
                                        shell_arg("file://" + page.string()));
    EXPECT_EQ(r.code, 0) << r.output;
    return r.output;
  }

  // Opens DIR/report.html; returns the number of comparisons it flips through.
  static int check_page(const fs::path& dir, int min_images) {
    const fs::path page = dir / "report.html";
    if (!fs::exists(page)) return ADD_FAILURE() << page << " was not written", -1;
    const std::string html = nns::read_file(page.string());
    EXPECT_EQ(html.find("<script"), std::string::npos) << "the page must read without JavaScript";
    EXPECT_EQ(html.find("http"), std::string::npos) << "the page must need no network";
    EXPECT_EQ(html.find("<i>"), std::string::npos) << "a file name became markup";

    const fs::path copy = dir / "report_check.html";
    std::string checked = html;
    checked.insert(checked.rfind("</body>"), kCheckScript);
    nns::write_file_atomic(copy.string(), checked);
    const std::string dom = headless("--dump-dom --window-size=1280,1600", copy);
    fs::remove(copy);
    const size_t at = dom.find("<pre id=\"nns-check\">");
    if (at == std::string::npos) return ADD_FAILURE() << "the check script did not run:\n" << dom.substr(0, 2000), -1;
    const std::string result = dom.substr(at + 20, dom.find("</pre>", at) - at - 20);
    int images = -1, comparisons = -1, injected = -1;
    EXPECT_EQ(std::sscanf(result.c_str(), "images=%d comparisons=%d injected=%d", &images, &comparisons, &injected), 3)
        << result;
    EXPECT_GE(images, min_images) << result;
    EXPECT_EQ(injected, 0) << result;
    EXPECT_NE(result.find("flip=ok "), std::string::npos) << result;
    EXPECT_NE(result.find(" nan_cells=0 "), std::string::npos) << "a table cell reads nan: " << result;
    EXPECT_NE(result.find("failed=[]"), std::string::npos) << "images that did not load: " << result;

    // The page as a person sees it (no script in it): not blank.
    const fs::path shot = dir / "report_screenshot.png";
    headless("--screenshot=" + shell_arg(shot) + " --window-size=1280,1600", page);
    int w = 0, h = 0;
    const std::vector<uint8_t> px = nns::testing::read_rgb8(shot.string(), &w, &h);
    std::map<std::array<uint8_t, 3>, int64_t> colours;
    for (size_t i = 0; i + 2 < px.size(); i += 3) ++colours[{px[i], px[i + 1], px[i + 2]}];
    int64_t most = 0;
    for (auto& [c, n] : colours) most = std::max(most, n);
    const int64_t pixels = int64_t(w) * h;
    EXPECT_EQ(w, 1280);
    EXPECT_GT(colours.size(), 50u) << shot << ": a blank page";
    EXPECT_GT(pixels - most, pixels / 50) << shot << ": under 2% of the screenshot differs from its background";
    // NNSHADE_REPORT_SHOTS=DIR keeps each page's screenshot as DIR/<run folder>.png, to
    // look at (the runs' folders are removed with the suite).
    if (const char* keep = std::getenv("NNSHADE_REPORT_SHOTS")) {
      const fs::path kept = fs::path(keep) / (dir.filename().string() + ".png");
      fs::create_directories(keep);
      fs::copy_file(shot, kept, fs::copy_options::overwrite_existing);
      std::printf("screenshot: %s\n", kept.c_str());
    }
    return comparisons;
  }

  // Every chart (*.svg) of DIR, inlined in one page opened at 1280 px: none has a text
  // (legend, axis label, tick) that runs off its image.
  static void check_charts(const fs::path& dir, int charts) {
    std::string html = "<!DOCTYPE html><html><head><meta charset=\"utf-8\"></head><body style=\"margin:0\">\n";
    for (auto& e : fs::directory_iterator(dir))
      if (e.path().extension() == ".svg") html += "<div>" + nns::read_file(e.path().string()) + "</div>\n";
    html += std::string(kChartScript) + "</body></html>\n";
    const fs::path page = dir / "charts_check.html";
    nns::write_file_atomic(page.string(), html);
    const std::string dom = headless("--dump-dom --window-size=1280,1600", page);
    fs::remove(page);
    const size_t at = dom.find("<pre id=\"nns-charts\">");
    if (at == std::string::npos)
      return (void)(ADD_FAILURE() << "the chart script did not run:\n" << dom.substr(0, 2000));
    const std::string result = dom.substr(at + 21, dom.find("</pre>", at) - at - 21);
    EXPECT_NE(result.find("charts=" + std::to_string(charts) + " "), std::string::npos) << dir << ": " << result;
    EXPECT_NE(result.find("cut=[]"), std::string::npos) << dir << ": chart text cut off: " << result;
  }

  static inline fs::path root_;
};

}  // namespace

TEST_F(ReportHtml, EvalAoPageShowsEveryImage) {
  const fs::path data = root_ / kOddFolder, out = root_ / "eval-ao";
  fs::create_directories(data);
  for (int v = 0; v < 3; ++v) {
    auto view = nns::fixtures::synthetic_view(48, 32, v, 16);
    view.scene = "path";
    view.world_to_camera = std::array<float, 16>{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    nns::data::write_view((data / ("path-p00-f00" + std::to_string(v) + ".exr")).string(), view);
  }
  const CommandResult r = run_app("eval-ao", "--data " + shell_arg(data) + " --out " + shell_arg(out) +
                                                 " --methods SSAO,HBAO --threads 2 --repeat 1 --previews 2");
  ASSERT_EQ(r.code, 0) << r.output;
  // 2 charts; 2 views x (truth + 2 methods x 2 images) on the stage and as thumbnails.
  EXPECT_EQ(check_page(out, 2 + 2 * 5 * 2), 2);
}

TEST_F(ReportHtml, TrainNnaoPageShowsTheLossChart) {
  const fs::path data = root_ / "nnao-data", out = root_ / "train-nnao";
  for (int v = 0; v < 4; ++v) {
    auto view = nns::fixtures::synthetic_view(40, 28, v, 16);
    view.scene = "synthetic" + std::to_string(v);
    fs::create_directories(data / (v % 2 ? "test" : "train"));
    nns::data::write_view((data / (v % 2 ? "test" : "train") / ("v" + std::to_string(v) + ".exr")).string(), view);
  }
  const CommandResult r =
      run_app("train-nnao", "--data " + shell_arg(data) + " --out " + shell_arg(out) +
                                " --preset grid --window 7 --points-per-view 96 --epochs 2 --seed 5 --dropout 0.3");
  ASSERT_EQ(r.code, 0) << r.output;
  // The train loss and the held-out MSE, each on a chart of its own.
  EXPECT_EQ(check_page(out, 2), 0);
  check_charts(out, 2);
  const std::string md = nns::read_file((out / "report.md").string());
  EXPECT_NE(md.find("| epoch | step | train_loss | test_mse |"), std::string::npos);
  // The checkpoint records 0.29999999999999999 (it reads back as the same double); people read 0.3.
  EXPECT_NE(md.find("| dropout | 0.3 |"), std::string::npos) << md;
  EXPECT_EQ(md.find("99999"), std::string::npos) << "a configuration value in 17 digits: " << md;
}

TEST_F(ReportHtml, TrainGanAndEvalGiPagesShowEveryImage) {
  const fs::path data = root_ / "gi-data", run = root_ / "train-gan", out = root_ / "eval-gi";
  nns::testing::write_dataset(data.string(), 3, 2);
  CommandResult r = run_app("train-gan", "--data " + shell_arg(data) + " --out " + shell_arg(run) +
                                             " --size 16 --ngf 4 --ndf 4 --levels 3 --d-layers 2 --epochs 2 "
                                             "--sample-every 2 --no-eval --seed 3 --validation-fraction 0");
  ASSERT_EQ(r.code, 0) << r.output;
  // The loss chart; the first and last samples, 5 images each on the stage and as thumbnails.
  EXPECT_EQ(check_page(run, 1 + 2 * 5 * 2), 2);
  check_charts(run, 1);
  // Epochs count from 1, as train-nnao's.
  const std::string log = nns::read_file((run / "metrics.jsonl").string());
  EXPECT_NE(log.find("\"epoch\":1,"), std::string::npos) << log;
  EXPECT_EQ(log.find("\"epoch\":0,"), std::string::npos) << log;
  EXPECT_EQ(nns::read_file((run / "loss.svg").string()).find("(log scale) (log scale)"), std::string::npos);
  r = run_app("eval-gi", "--data " + shell_arg(data) + " --model " + shell_arg(run / "G.blob") + " --out " +
                             shell_arg(out) + " --previews 2");
  ASSERT_EQ(r.code, 0) << r.output;
  // 3 charts (SSIM, linear MSE, FLIP against time); 2 frames x (truth + 3 rows x 2
  // images), on the stage and as thumbnails.
  EXPECT_EQ(check_page(out, 3 + 2 * 7 * 2), 2);
  check_charts(out, 3);
}
