// report.md and report.html from one Report: every user-controlled string (a model
// label, a file name, a data path) is escaped, so a hostile name cannot inject markup;
// the markdown and the page show the same rows.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <set>
#include <string>

#include "core/atomic_file.h"
#include "report/html_report.h"

using namespace nns::report;

namespace {

size_t count(const std::string& s, const std::string& what) {
  size_t n = 0;
  for (size_t i = s.find(what); i != std::string::npos; i = s.find(what, i + 1)) ++n;
  return n;
}

// Every tag of `page` outside its <style> that the writer does not write, or that
// carries an attribute starting with "on"; "" when there is none.
std::string stray_tags(const std::string& page) {
  static const std::set<std::string> ours = {
      "!DOCTYPE", "html", "head", "meta",   "title",      "style", "body",    "main",  "h1",    "h2",    "h3",
      "nav",      "a",    "p",    "ul",     "li",         "code",  "strong",  "div",   "table", "thead", "tbody",
      "tr",       "th",   "td",   "figure", "figcaption", "img",   "section", "input", "label", "b",     "br"};
  std::string stray;
  for (size_t i = page.find('<'); i != std::string::npos; i = page.find('<', i + 1)) {
    const size_t end = page.find('>', i);
    const std::string tag = page.substr(i + 1, end - i - 1);
    const std::string name = tag.substr(tag[0] == '/', tag.find_first_of(" >") - (tag[0] == '/'));
    bool handler = false, quoted = false;  // an attribute name (outside quotes) "on..."
    for (size_t k = 0; k < tag.size(); ++k) {
      if (tag[k] == '"') quoted = !quoted;
      else if (!quoted && tag[k] == ' ') handler |= tag.compare(k + 1, 2, "on") == 0;
    }
    if (!ours.count(name) || handler || quoted) stray += "<" + tag + "> ";
    if (name == "style") i = page.find("</style>", i);
  }
  return stray;
}

const std::string kHostile = "<script>alert('x')</script>\"><img src=x onerror=alert(1)>&amp;";

}  // namespace

TEST(HtmlReport, EscapesTheFiveCharacters) {
  EXPECT_EQ(html_escape("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&#39;");
  EXPECT_EQ(html_escape("plain text 1.5"), "plain text 1.5");
}

TEST(HtmlReport, UrlPathKeepsOnlyPathCharacters) {
  EXPECT_EQ(url_path("previews/room-1_p00.png"), "previews/room-1_p00.png");
  EXPECT_EQ(url_path("a b#c?.png"), "a%20b%23c%3F.png");
  // No scheme can survive (':' is encoded), nor a quote that would end the attribute.
  EXPECT_EQ(url_path("javascript:alert(1)"), "javascript%3Aalert%281%29");
  EXPECT_EQ(url_path("x\"onload=\"y"), "x%22onload%3D%22y");
}

TEST(HtmlReport, InlineMarkdownIsEscapedAndUnclosedMarkersAreClosed) {
  EXPECT_EQ(inline_html("**holds**: `a<b`"), "<strong>holds</strong>: <code>a&lt;b</code>");
  EXPECT_EQ(inline_html("`**not bold**`"), "<code>**not bold**</code>");
  EXPECT_EQ(inline_html("data `/tmp/odd"), "data <code>/tmp/odd</code>");
  EXPECT_EQ(inline_html("**a `b"), "<strong>a <code>b</code></strong>");
}

TEST(HtmlReport, MarkdownTableEscapesPipes) {
  EXPECT_EQ(markdown(Table{{"model", "MSE"}, {{"a|b", "0.5"}}}), "| model | MSE |\n|---|---|\n| a\\|b | 0.5 |\n");
}

TEST(HtmlReport, HostileNamesAreInertInThePage) {
  Report r("eval of " + kHostile);
  r.heading(kHostile).text("Data: `" + kHostile + "`").list({kHostile});
  r.table({{"model", "MSE"}, {{kHostile, "0.25"}}});
  r.chart("chart\" onerror=\"alert(1).svg", kHostile, kHostile);
  r.comparison({kHostile, {{kHostile, "previews/" + kHostile + ".png", kHostile}, {"truth", "t.png", ""}}});
  const std::string page = r.html();
  // The only tags are the page's own, none with an event handler.
  EXPECT_EQ(stray_tags(page), "");
  EXPECT_EQ(page.find("alert('x')"), std::string::npos);
  EXPECT_EQ(count(page, "<img "), 1u + 2u * 2u);  // the chart; the stage and a thumbnail per image
  EXPECT_NE(page.find("&lt;script&gt;alert(&#39;x&#39;)&lt;/script&gt;"), std::string::npos);
  EXPECT_NE(page.find("&amp;amp;"), std::string::npos);  // an entity in a name stays text
  EXPECT_NE(page.find("src=\"chart%22%20onerror%3D%22alert%281%29.svg\""), std::string::npos);
}

TEST(HtmlReport, PageAndMarkdownShowTheSameRows) {
  Report r("AO");
  r.heading("Results").table({{"method", "samples", "MSE"}, {{"SSAO", "16", "0.0123"}, {"HBAO", "64", "nan"}}});
  r.chart("speed.svg", "speed vs accuracy");
  r.comparison(
      {"view 0", {{"ground truth", "previews/v_gt.png", ""}, {"SSAO, 16", "previews/v_ssao.png", "MSE 0.01"}}});
  const std::string md = r.markdown(), page = r.html();
  EXPECT_EQ(md.rfind("# AO\n\n## Results\n\n| method | samples | MSE |\n|---|---|---|\n| SSAO | 16 | 0.0123 |\n", 0),
            0u)
      << md;
  EXPECT_NE(md.find("![speed vs accuracy](speed.svg)"), std::string::npos) << md;
  EXPECT_NE(md.find("| SSAO, 16 | MSE 0.01 | ![SSAO, 16](previews/v_ssao.png) |"), std::string::npos) << md;
  EXPECT_NE(page.find("<tr><td>SSAO</td><td class=\"n\">16</td><td class=\"n\">0.0123</td></tr>"), std::string::npos)
      << page;
  // A radio button per image, the first checked: the page flips without JavaScript.
  EXPECT_EQ(count(page, "type=\"radio\" name=\"cmp0\""), 2u);
  EXPECT_EQ(count(page, " checked>"), 1u);
  EXPECT_NE(page.find(".cmp>input:nth-of-type(2):checked~.stage>figure:nth-of-type(2){display:block}"),
            std::string::npos);
  EXPECT_NE(page.find("<a href=\"#s1\">Results</a>"), std::string::npos);
}

TEST(HtmlReport, WritesBothFiles) {
  const auto dir = std::filesystem::temp_directory_path() / ("nns_html_report_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  Report r("run");
  r.text("done");
  r.write(dir.string());
  EXPECT_EQ(nns::read_file((dir / "report.md").string()), r.markdown());
  EXPECT_EQ(nns::read_file((dir / "report.html").string()), r.html());
  std::filesystem::remove_all(dir);
}
