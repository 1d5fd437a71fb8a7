#include "report/html_report.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "core/atomic_file.h"

namespace nns::report {

std::string html_escape(std::string_view s) {
  std::string o;
  o.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&':
        o += "&amp;";
        break;
      case '<':
        o += "&lt;";
        break;
      case '>':
        o += "&gt;";
        break;
      case '"':
        o += "&quot;";
        break;
      case '\'':
        o += "&#39;";
        break;
      default:
        o += c;
    }
  }
  return o;
}

std::string url_path(std::string_view path) {
  static const char* hex = "0123456789ABCDEF";
  std::string o;
  for (char ch : path) {
    const auto c = static_cast<unsigned char>(ch);
    if (std::isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~' || c == '/') {
      o += char(c);
    } else {
      o += '%';
      o += hex[c >> 4];
      o += hex[c & 15];
    }
  }
  return o;
}

std::string inline_html(std::string_view md) {
  std::string o;
  std::vector<const char*> open;  // closing tags, innermost last
  auto toggle = [&](const char* tag, const char* close) {
    if (!open.empty() && open.back() == close) {
      o += close;
      open.pop_back();
    } else {
      o += tag;
      open.push_back(close);
    }
  };
  const auto in_code = [&] { return std::find(open.begin(), open.end(), std::string_view("</code>")) != open.end(); };
  for (size_t i = 0; i < md.size(); ++i) {
    if (md[i] == '`') {
      toggle("<code>", "</code>");
    } else if (!in_code() && md.compare(i, 2, "**") == 0) {
      toggle("<strong>", "</strong>");
      ++i;
    } else {
      o += html_escape(md.substr(i, 1));
    }
  }
  // An unclosed marker (a path holding a backtick) must not leave the rest of the page
  // inside <code>.
  for (auto it = open.rbegin(); it != open.rend(); ++it) o += *it;
  return o;
}

std::string markdown(const Table& t) {
  auto row = [](const std::vector<std::string>& cells) {
    std::string s = "|";
    for (auto& c : cells) {
      std::string e;
      for (char ch : c) e += ch == '|' ? std::string("\\|") : std::string(1, ch);
      s += " " + e + " |";
    }
    return s + "\n";
  };
  std::string s = row(t.header) + "|";
  for (size_t i = 0; i < t.header.size(); ++i) s += "---|";
  s += "\n";
  for (auto& r : t.rows) s += row(r);
  return s;
}

Report& Report::heading(std::string text) {
  return blocks_.push_back({Kind::heading, {std::move(text)}, {}, {}}), *this;
}
Report& Report::text(std::string p) { return blocks_.push_back({Kind::text, {std::move(p)}, {}, {}}), *this; }
Report& Report::list(std::vector<std::string> items) {
  return blocks_.push_back({Kind::list, std::move(items), {}, {}}), *this;
}
Report& Report::table(Table t) { return blocks_.push_back({Kind::table, {}, std::move(t), {}}), *this; }
Report& Report::chart(std::string file, std::string caption, std::string note) {
  return blocks_.push_back({Kind::chart, {std::move(file), std::move(caption), std::move(note)}, {}, {}}), *this;
}
Report& Report::comparison(Comparison c) { return blocks_.push_back({Kind::comparison, {}, {}, std::move(c)}), *this; }

std::string Report::markdown() const {
  std::string s = "# " + title_ + "\n\n";
  for (auto& b : blocks_) {
    switch (b.kind) {
      case Kind::heading:
        s += "## " + b.s[0] + "\n\n";
        break;
      case Kind::text:
        s += b.s[0] + "\n\n";
        break;
      case Kind::list:
        for (auto& item : b.s) s += "- " + item + "\n";
        s += "\n";
        break;
      case Kind::table:
        s += report::markdown(b.table) + "\n";
        break;
      case Kind::chart:
        s += "![" + b.s[1] + "](" + url_path(b.s[0]) + ")\n" + (b.s[2].empty() ? "" : "(" + b.s[2] + ")\n") + "\n";
        break;
      case Kind::comparison: {
        Table t{{"image", "numbers", b.comparison.title}, {}};
        for (auto& im : b.comparison.images)
          t.rows.push_back({im.label, im.numbers, "![" + im.label + "](" + url_path(im.file) + ")"});
        s += report::markdown(t) + "\n";
        break;
      }
    }
  }
  return s;
}

namespace {

// Sized for the largest comparison on the page: the k-th radio button shows the k-th
// image of the stage and marks the k-th thumbnail.
std::string style(size_t max_images) {
  std::string s =
      "body{font:15px/1.45 system-ui,-apple-system,'Segoe UI',sans-serif;margin:0;color:#1d1d1f;background:#fff}"
      "main{max-width:1120px;margin:0 auto;padding:12px 24px 48px}"
      "h1{font-size:26px;margin:12px 0 4px}h2{font-size:20px;margin:28px 0 8px;border-bottom:1px solid #ddd}"
      "nav{font-size:14px;margin:4px 0 12px}nav a{margin-right:14px}"
      "code{background:#f2f2f6;padding:0 3px;border-radius:3px;font-size:90%}"
      ".scroll{overflow-x:auto}table{border-collapse:collapse;margin:6px 0 14px;font-size:13px}"
      "th,td{border:1px solid #d0d0d7;padding:3px 8px;white-space:nowrap}th{background:#eef0f5;text-align:left}"
      "td.n{text-align:right;font-variant-numeric:tabular-nums}tbody tr:nth-child(even){background:#f8f8fb}"
      "figure{margin:8px 0 16px}figure.chart img{max-width:100%;height:auto;border:1px solid #e4e4ea}"
      "figcaption{font-size:13px;color:#555}"
      ".cmp{border:1px solid #d0d0d7;border-radius:6px;padding:6px 12px 12px;margin:12px 0}"
      ".cmp h3{font-size:15px;margin:4px 0 2px}.hint{font-size:12px;color:#666;margin:0 0 6px}"
      ".cmp>input{position:absolute;opacity:0;width:1px;height:1px}"
      ".stage>figure{display:none;margin:0 0 8px}"
      ".stage img{width:min(100%,512px);height:auto;image-rendering:pixelated;background:#000}"
      ".thumbs{display:flex;flex-wrap:wrap;gap:6px}"
      ".thumbs label{cursor:pointer;width:132px;font-size:12px;line-height:1.3;border:2px solid transparent;"
      "border-radius:4px;padding:2px}"
      ".thumbs img{display:block;width:100%;height:auto;image-rendering:pixelated;background:#000}"
      ".cmp>input:focus-visible~.thumbs{outline:1px dashed #888}";
  for (size_t k = 1; k <= max_images; ++k) {
    const std::string n = std::to_string(k);
    s += ".cmp>input:nth-of-type(" + n + "):checked~.stage>figure:nth-of-type(" + n + "){display:block}";
    s += ".cmp>input:nth-of-type(" + n + "):checked~.thumbs>label:nth-of-type(" + n +
         "){border-color:#0a63c9;background:#eaf2ff}";
  }
  return s;
}

bool is_number(const std::string& s) {
  if (s.empty()) return false;
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return *end == '\0';
}

std::string table_html(const Table& t) {
  std::string s = "<div class=\"scroll\"><table><thead><tr>";
  for (auto& h : t.header) s += "<th>" + inline_html(h) + "</th>";
  s += "</tr></thead><tbody>\n";
  for (auto& r : t.rows) {
    s += "<tr>";
    for (auto& c : r) s += (is_number(c) ? "<td class=\"n\">" : "<td>") + inline_html(c) + "</td>";
    s += "</tr>\n";
  }
  return s + "</tbody></table></div>\n";
}

std::string comparison_html(const Comparison& c, size_t index) {
  const std::string group = "cmp" + std::to_string(index);
  std::string inputs, stage, thumbs;
  for (size_t k = 0; k < c.images.size(); ++k) {
    const ComparisonImage& im = c.images[k];
    const std::string id = group + "-" + std::to_string(k), src = url_path(im.file), label = html_escape(im.label);
    const std::string numbers = html_escape(im.numbers);
    inputs += "<input type=\"radio\" name=\"" + group + "\" id=\"" + id + "\"" + (k == 0 ? " checked" : "") + ">";
    stage += "<figure><img src=\"" + src + "\" alt=\"" + label + "\"><figcaption><b>" + label + "</b>" +
             (numbers.empty() ? "" : " — " + numbers) + "</figcaption></figure>";
    thumbs += "<label for=\"" + id + "\"><img src=\"" + src + "\" alt=\"\">" + label +
              (numbers.empty() ? "" : "<br>" + numbers) + "</label>";
  }
  return "<section class=\"cmp\"><h3>" + html_escape(c.title) + "</h3><p class=\"hint\">Click a thumbnail to show it " +
         "large; the arrow keys then flip through them.</p>" + inputs + "<div class=\"stage\">" + stage +
         "</div><div class=\"thumbs\">" + thumbs + "</div></section>\n";
}

}  // namespace

std::string Report::html() const {
  size_t max_images = 0, sections = 0, comparisons = 0;
  std::string nav, body;
  for (auto& b : blocks_) {
    switch (b.kind) {
      case Kind::heading: {
        const std::string id = std::string("s").append(std::to_string(++sections));
        nav += "<a href=\"#" + id + "\">" + inline_html(b.s[0]) + "</a>";
        body += "<h2 id=\"" + id + "\">" + inline_html(b.s[0]) + "</h2>\n";
        break;
      }
      case Kind::text:
        body += "<p>" + inline_html(b.s[0]) + "</p>\n";
        break;
      case Kind::list:
        body += "<ul>";
        for (auto& item : b.s) body += "<li>" + inline_html(item) + "</li>";
        body += "</ul>\n";
        break;
      case Kind::table:
        body += table_html(b.table);
        break;
      case Kind::chart: {
        const std::string src = url_path(b.s[0]);
        body += "<figure class=\"chart\"><a href=\"" + src + "\"><img src=\"" + src + "\" alt=\"" +
                html_escape(b.s[1]) + "\"></a>" +
                (b.s[2].empty() ? "" : "<figcaption>" + html_escape(b.s[2]) + "</figcaption>") + "</figure>\n";
        break;
      }
      case Kind::comparison:
        max_images = std::max(max_images, b.comparison.images.size());
        body += comparison_html(b.comparison, comparisons++);
        break;
    }
  }
  return "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
         "<meta name=\"viewport\" content=\"width=device-width,initial-scale=1\"><title>" +
         html_escape(title_) + "</title><style>" + style(max_images) + "</style></head>\n<body><main><h1>" +
         html_escape(title_) + "</h1>\n" + (nav.empty() ? "" : "<nav>" + nav + "</nav>\n") + body +
         "</main></body></html>\n";
}

void Report::write(const std::string& dir) const {
  const std::filesystem::path d(dir);
  write_file_atomic((d / "report.md").string(), markdown());
  write_file_atomic((d / "report.html").string(), html());
}

}  // namespace nns::report
