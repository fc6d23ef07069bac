// The report's document model and its two writers (apps/report_doc.hpp).
#include "apps/report_doc.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

// stb's reader, resizer and writer, private to this file (render/png.cpp has its own writer).
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_RESIZE_STATIC
#define STB_IMAGE_RESIZE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>
#include <stb/stb_image_resize.h>
#include <stb/stb_image_write.h>

namespace rb::app::doc {

namespace fs = std::filesystem;

namespace {

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r\n") - a + 1);
}
bool starts(const std::string& s, const char* p) { return s.rfind(p, 0) == 0; }

// The cells of a pipe-table row: split at '|' outside code spans, "\|" kept as '|'.
std::vector<std::string> cells(const std::string& line) {
  std::string s = trim(line);
  if (starts(s, "|")) s.erase(0, 1);
  if (!s.empty() && s.back() == '|' && (s.size() < 2 || s[s.size() - 2] != '\\')) s.pop_back();
  std::vector<std::string> out;
  std::string cur;
  bool code = false;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (c == '\\' && i + 1 < s.size() && s[i + 1] == '|') {
      cur += '|';
      ++i;
      continue;
    }
    if (c == '`') code = !code;
    if (c == '|' && !code) {
      out.push_back(trim(cur));
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(trim(cur));
  return out;
}

// "![alt](src)" alone on a line: the image's alt and source.
bool image_line(const std::string& line, std::string& alt, std::string& src) {
  static const std::regex re(R"(^!\[([^\]]*)\]\(([^)\s]+)\)$)");
  std::smatch m;
  const std::string t = trim(line);
  if (!std::regex_match(t, m, re)) return false;
  alt = m[1];
  src = m[2];
  return true;
}

std::string slug(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (std::isalnum(static_cast<unsigned char>(c))) o += char(std::tolower(static_cast<unsigned char>(c)));
    else if (!o.empty() && o.back() != '-') o += '-';
  }
  while (!o.empty() && o.back() == '-') o.pop_back();
  return o.empty() ? "section" : o;
}

std::string html_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

// Inline markdown (code spans, images, links, **bold**, _emphasis_ at word edges) as HTML.
std::string inline_html(const std::string& s) {
  std::string o;
  std::size_t i = 0;
  bool bold = false, em = false;
  auto word = [&](std::size_t k) { return k < s.size() && std::isalnum(static_cast<unsigned char>(s[k])); };
  while (i < s.size()) {
    const char c = s[i];
    if (c == '`') {
      const auto e = s.find('`', i + 1);
      if (e != std::string::npos) {
        o += "<code>" + html_escape(s.substr(i + 1, e - i - 1)) + "</code>";
        i = e + 1;
        continue;
      }
    }
    if ((c == '!' && i + 1 < s.size() && s[i + 1] == '[') || c == '[') {
      const std::size_t lb = c == '!' ? i + 1 : i;
      const auto rb = s.find("](", lb);
      const auto rp = rb == std::string::npos ? rb : s.find(')', rb + 2);
      if (rb != std::string::npos && rp != std::string::npos && s.find('\n', lb) > rp) {
        const std::string text = s.substr(lb + 1, rb - lb - 1), href = s.substr(rb + 2, rp - rb - 2);
        if (c == '!')
          o += "<img src=\"" + html_escape(href) + "\" alt=\"" + html_escape(text) + "\">";
        else
          o += "<a href=\"" + html_escape(href) + "\">" + inline_html(text) + "</a>";
        i = rp + 1;
        continue;
      }
    }
    if (c == '*' && i + 1 < s.size() && s[i + 1] == '*') {
      o += bold ? "</strong>" : "<strong>";
      bold = !bold;
      i += 2;
      continue;
    }
    if (c == '_' && (em ? !word(i + 1) : (i == 0 || !word(i - 1)) && word(i + 1)) && (em || s.find('_', i + 1) != std::string::npos)) {
      o += em ? "</em>" : "<em>";
      em = !em;
      ++i;
      continue;
    }
    o += html_escape(std::string(1, c));
    ++i;
  }
  if (em) o += "</em>";
  if (bold) o += "</strong>";
  return o;
}

std::string strip_number(const std::string& title) {
  static const std::regex re(R"(^\d+(\.\d+)*\.?\s+)");
  return std::regex_replace(title, re, "");
}

// A caption line before an image: "`name`" alone.
bool caption_line(const std::string& text, std::string& cap) {
  const std::string t = trim(text);
  if (t.size() > 2 && t.front() == '`' && t.back() == '`' && t.find('`', 1) == t.size() - 1 && t.find('\n') == std::string::npos) {
    cap = t.substr(1, t.size() - 2);
    return true;
  }
  return false;
}

}  // namespace

Document parse_markdown(const std::string& md) {
  Document d;
  std::vector<std::string> lines;
  {
    std::istringstream in(md);
    std::string l;
    while (std::getline(in, l)) lines.push_back(l);
  }
  std::string para;
  auto flush = [&] {
    if (!trim(para).empty()) d.blocks.push_back({Block::Kind::text, 0, trim(para), "", {}, {}});
    para.clear();
  };
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string& l = lines[i];
    const std::string t = trim(l);
    if (starts(t, "```")) {
      flush();
      std::string code;
      for (++i; i < lines.size() && !starts(trim(lines[i]), "```"); ++i) code += lines[i] + "\n";
      d.blocks.push_back({Block::Kind::code, 0, code, "", {}, {}});
      continue;
    }
    if (starts(t, "<!--")) {
      flush();
      d.blocks.push_back({Block::Kind::comment, 0, t, "", {}, {}});
      continue;
    }
    if (starts(t, "#")) {
      std::size_t n = 0;
      while (n < t.size() && t[n] == '#') ++n;
      if (n <= 4 && n < t.size() && t[n] == ' ') {
        flush();
        if (n == 1 && d.title.empty()) d.title = trim(t.substr(n));
        else d.blocks.push_back({Block::Kind::heading, int(n), trim(t.substr(n)), "", {}, {}});
        continue;
      }
    }
    if (starts(t, "|") && i + 1 < lines.size() && starts(trim(lines[i + 1]), "|") && trim(lines[i + 1]).find("---") != std::string::npos) {
      flush();
      Block b{Block::Kind::table, 0, "", "", {}, {}};
      b.table.head = cells(t);
      for (const auto& a : cells(lines[i + 1])) {
        const bool l0 = starts(a, ":"), r0 = !a.empty() && a.back() == ':';
        b.table.align.push_back(l0 && r0 ? "center" : r0 ? "right" : l0 ? "left" : "");
      }
      for (i += 2; i < lines.size() && starts(trim(lines[i]), "|"); ++i) {
        auto r = cells(lines[i]);
        r.resize(b.table.head.size());
        b.table.rows.push_back(r);
      }
      --i;
      d.blocks.push_back(b);
      continue;
    }
    std::string alt, src;
    if (image_line(t, alt, src)) {
      flush();
      Block b{Block::Kind::gallery, 0, "", "", {}, {}};
      b.pictures.push_back({alt, src, ""});
      d.blocks.push_back(b);
      continue;
    }
    if (t.empty()) {
      flush();
      continue;
    }
    para += l + "\n";
  }
  flush();
  return d;
}

bool make_thumbnail(const fs::path& png, const fs::path& thumb, int width, std::string* why) {
  int w = 0, h = 0, n = 0;
  unsigned char* px = stbi_load(png.string().c_str(), &w, &h, &n, 3);
  if (!px) {
    if (why) *why = png.string() + ": " + (stbi_failure_reason() ? stbi_failure_reason() : "cannot read");
    return false;
  }
  const int tw = std::min(width, w), th = std::max(1, int(double(h) * tw / w + 0.5));
  std::vector<unsigned char> out(std::size_t(tw) * std::size_t(th) * 3);
  const bool ok = stbir_resize_uint8(px, w, h, 0, out.data(), tw, th, 0, 3) != 0;
  stbi_image_free(px);
  if (!ok || !stbi_write_png(thumb.string().c_str(), tw, th, 3, out.data(), tw * 3)) {
    if (why) *why = thumb.string() + ": cannot write the thumbnail";
    return false;
  }
  return true;
}

void organise(Document& d, const std::vector<Goal>& goals, const fs::path& out, const OrganiseOptions& o) {
  // 1. Galleries: a run of images (each with an optional caption line before it) becomes one grid.
  {
    std::vector<Block> b;
    for (std::size_t i = 0; i < d.blocks.size(); ++i) {
      std::vector<Picture> run;
      std::size_t j = i;
      while (j < d.blocks.size()) {
        std::string cap;
        if (d.blocks[j].kind == Block::Kind::text && j + 1 < d.blocks.size() && d.blocks[j + 1].kind == Block::Kind::gallery &&
            caption_line(d.blocks[j].text, cap)) {
          Picture p = d.blocks[j + 1].pictures.front();
          p.caption = cap;
          run.push_back(p);
          j += 2;
        } else if (d.blocks[j].kind == Block::Kind::gallery) {
          run.push_back(d.blocks[j].pictures.front());
          ++j;
        } else {
          break;
        }
      }
      if (run.size() >= o.gallery_min) {
        Block g{Block::Kind::gallery, 0, "", "", {}, run};
        fs::create_directories(out / "thumbs");
        for (auto& p : g.pictures) {
          const fs::path t = fs::path("thumbs") / fs::path(p.src).filename();
          std::string why;
          if (make_thumbnail(out / p.src, out / t, o.thumb_width, &why)) p.thumb = t.generic_string();
        }
        b.push_back(g);
        i = j - 1;
      } else {
        b.push_back(d.blocks[i]);
      }
    }
    d.blocks = std::move(b);
  }
  // 2. Numbered sections and their anchors.
  int n2 = 0, n3 = 0;
  std::map<std::string, std::string> section_id;  // title without number -> id
  std::vector<std::pair<std::string, std::string>> section_title;  // id -> numbered title, in order
  for (auto& b : d.blocks) {
    if (b.kind != Block::Kind::heading || b.level > 3) continue;
    const std::string bare = strip_number(b.text);
    if (b.level == 2) {
      ++n2;
      n3 = 0;
      b.text = fmt::format("{}. {}", n2, bare);
      b.id = fmt::format("s{}-{}", n2, slug(bare));
      section_id[bare] = b.id;
      section_title.push_back({b.id, b.text});
    } else {
      ++n3;
      b.text = fmt::format("{}.{} {}", n2, n3, bare);
      b.id = fmt::format("s{}-{}-{}", n2, n3, slug(bare));
    }
  }
  // 3. Long tables to the appendix, each replaced by a line that links to it.
  std::vector<Block> appendix;
  {
    std::vector<Block> b;
    std::string where = d.title;
    int k = 0;
    for (auto& blk : d.blocks) {
      if (blk.kind == Block::Kind::heading) where = blk.text;
      if (blk.kind == Block::Kind::table && blk.table.rows.size() > o.appendix_rows) {
        ++k;
        const std::string id = fmt::format("appendix-{}", k);
        appendix.push_back({Block::Kind::heading, 3, fmt::format("A.{} {}", k, where), id, {}, {}});
        appendix.push_back(blk);
        b.push_back({Block::Kind::text, 0,
                     fmt::format("The table of this section ({} rows) is in [Appendix A.{}](#{}).", blk.table.rows.size(), k, id),
                     "", {}, {}});
      } else {
        b.push_back(std::move(blk));
      }
    }
    d.blocks = std::move(b);
  }
  // 4. The summary of every goal and the table of contents, after the opening paragraphs.
  std::vector<Block> top;
  top.push_back({Block::Kind::heading, 2, "Summary: the goals", "summary", {}, {}});
  {
    Block t{Block::Kind::table, 0, "", "", {}, {}};
    t.table.head = {"goal", "measured in this run", "met", "figure", "section"};
    t.table.align = {"", "", "", "", ""};
    int met = 0, not_met = 0, undecided = 0, unmeasured = 0;
    for (const Goal& g : goals) {
      std::string sec = "-";
      for (const auto& [bare, id] : section_id)
        if (starts(bare, g.section.c_str()))
          for (const auto& [sid, title] : section_title)
            if (sid == id) sec = fmt::format("[{}](#{})", title, id);
      const std::string fig = g.figure.empty() ? "-" : fmt::format("[chart]({})", g.figure);
      t.table.rows.push_back({g.goal, g.measured, goal_cell(g.met), fig, sec});
      (g.met == kGoalMet ? met : g.met == kGoalNotMet ? not_met : g.met == kGoalUndecided ? undecided : unmeasured)++;
    }
    top.push_back({Block::Kind::text, 0,
                   fmt::format("{} goals: **{} met**, **{} not met**{}{}. Each is checked against this run's figures in the section "
                               "named beside it, with the reason it is a goal. A goal on a ratio measured in paired rounds is met "
                               "only when the ratio's 95 % interval clears its target, and undecided when the interval straddles it.",
                               goals.size(), met, not_met, undecided ? fmt::format(", {} undecided", undecided) : "",
                               unmeasured ? fmt::format(", {} not measured", unmeasured) : ""),
                   "", {}, {}});
    top.push_back(t);
  }
  top.push_back({Block::Kind::heading, 2, "Contents", "contents", {}, {}});
  {
    std::string toc;
    for (const auto& b : d.blocks)
      if (b.kind == Block::Kind::heading && (b.level == 2 || b.level == 3) && !b.id.empty())
        toc += fmt::format("{}- [{}](#{})\n", b.level == 3 ? "  " : "", b.text, b.id);
    if (!appendix.empty()) toc += "- [Appendix A. Long tables](#appendix)\n";
    top.push_back({Block::Kind::text, 0, toc, "", {}, {}});
  }
  std::size_t at = 0;
  while (at < d.blocks.size() && d.blocks[at].kind == Block::Kind::text) ++at;
  d.blocks.insert(d.blocks.begin() + std::ptrdiff_t(at), top.begin(), top.end());
  if (!appendix.empty()) {
    d.blocks.push_back({Block::Kind::heading, 2, "Appendix A. Long tables", "appendix", {}, {}});
    d.blocks.insert(d.blocks.end(), appendix.begin(), appendix.end());
  }
}

std::string to_markdown(const Document& d) {
  std::string md = "# " + d.title + "\n\n";
  for (const auto& b : d.blocks) {
    switch (b.kind) {
      case Block::Kind::heading:
        if (!b.id.empty()) md += "<a id=\"" + b.id + "\"></a>\n";
        md += std::string(std::size_t(b.level), '#') + " " + b.text + "\n\n";
        break;
      case Block::Kind::text: md += b.text + "\n\n"; break;
      case Block::Kind::code: md += "```\n" + b.text + "```\n\n"; break;
      case Block::Kind::comment: md += b.text + "\n"; break;
      case Block::Kind::table: {
        auto row = [](const std::vector<std::string>& r) {
          std::string s = "|";
          for (const auto& c : r) {
            std::string e;
            bool code = false;
            for (char ch : c) {
              if (ch == '`') code = !code;
              e += (ch == '|' && !code) ? std::string("\\|") : std::string(1, ch);
            }
            s += " " + e + " |";
          }
          return s + "\n";
        };
        md += row(b.table.head);
        std::string sep = "|";
        for (const auto& a : b.table.align) sep += a == "right" ? "---:|" : a == "center" ? ":---:|" : a == "left" ? ":---|" : "---|";
        md += sep + "\n";
        for (const auto& r : b.table.rows) md += row(r);
        md += "\n";
        break;
      }
      case Block::Kind::gallery: {
        if (b.pictures.size() == 1 && b.pictures[0].thumb.empty()) {
          md += "![" + b.pictures[0].caption + "](" + b.pictures[0].src + ")\n\n";
          break;
        }
        // A grid of thumbnails, four to a row, each linking to the full image.
        constexpr std::size_t kCols = 4;
        md += "|";
        for (std::size_t c = 0; c < kCols; ++c) md += "   |";
        md += "\n|";
        for (std::size_t c = 0; c < kCols; ++c) md += ":---:|";
        md += "\n";
        for (std::size_t i = 0; i < b.pictures.size(); i += kCols) {
          md += "|";
          for (std::size_t c = 0; c < kCols; ++c) {
            if (i + c < b.pictures.size()) {
              const Picture& p = b.pictures[i + c];
              md += fmt::format(" [![{0}]({1})]({2})<br>`{0}` |", p.caption, p.thumb.empty() ? p.src : p.thumb, p.src);
            } else {
              md += "   |";
            }
          }
          md += "\n";
        }
        md += "\n";
        break;
      }
    }
  }
  return md;
}

namespace {

const char* kStyle = R"(
body{font:15px/1.5 system-ui,-apple-system,"Segoe UI",sans-serif;margin:0;color:#1d2330;background:#fff}
main{max-width:1180px;margin:0 auto;padding:1.5em 2em 4em}
h1{font-size:1.9em;margin:.3em 0}h2{border-bottom:2px solid #dde3ee;padding-bottom:.2em;margin-top:2em}
h3{margin-top:1.6em}a{color:#1f5fbf}code{background:#f1f3f7;padding:0 .25em;border-radius:3px;font-size:.92em}
pre{background:#f1f3f7;padding:.8em;overflow:auto}
.tablewrap{overflow-x:auto;margin:.8em 0}
table{border-collapse:collapse;font-size:.88em}th,td{border:1px solid #d6dbe5;padding:.25em .55em;vertical-align:top}
th{background:#eef2f8;cursor:pointer;user-select:none;position:sticky;top:0}th.sorted-asc::after{content:" \25B2"}th.sorted-desc::after{content:" \25BC"}
tr:nth-child(even) td{background:#fafbfd}td.right,th.right{text-align:right}td.center,th.center{text-align:center}
img{max-width:100%}.grid{display:grid;grid-template-columns:repeat(auto-fill,minmax(200px,1fr));gap:14px;margin:1em 0}
.grid figure{margin:0;text-align:center;font-size:.85em}.grid img{border:1px solid #d6dbe5;display:block;margin:0 auto .3em}
nav.toc>ul{columns:2;margin:.3em 0}nav.toc ul ul{columns:1;break-inside:avoid}nav.toc li{break-inside:avoid}
)";

// Sorting: a click on a header sorts the table's rows by that column (numbers by value, with
// thousands separators, units and signs read; text otherwise), a second click reverses. On load,
// every image that did not decode is reported as a console error (report-check fails on it).
const char* kScript = R"(
(function(){
function key(t){var s=t.replace(/[,\s]/g,'').replace(/^[~<>=+]+/,'');var m=s.match(/^-?[0-9]*\.?[0-9]+(e[-+]?[0-9]+)?/i);return m?parseFloat(m[0]):null}
function sortBy(th){var table=th.closest('table'),i=Array.prototype.indexOf.call(th.parentNode.children,th);
var body=table.tBodies[0],rows=Array.prototype.slice.call(body.rows),asc=!th.classList.contains('sorted-asc');
rows.sort(function(a,b){var x=a.cells[i]?a.cells[i].textContent.trim():'',y=b.cells[i]?b.cells[i].textContent.trim():'';
var p=key(x),q=key(y),c=(p!==null&&q!==null)?p-q:x.localeCompare(y);return asc?c:-c});
rows.forEach(function(r){body.appendChild(r)});
Array.prototype.forEach.call(th.parentNode.children,function(h){h.classList.remove('sorted-asc','sorted-desc')});
th.classList.add(asc?'sorted-asc':'sorted-desc')}
document.querySelectorAll('table.sortable th').forEach(function(th){th.title='click to sort';th.addEventListener('click',function(){sortBy(th)})});
window.addEventListener('load',function(){document.querySelectorAll('img').forEach(function(im){
if(!im.complete||im.naturalWidth===0)console.error('broken image: '+im.getAttribute('src'))})});
})();
)";

std::string html_text(const std::string& text) {
  // Paragraphs, "- " lists (two-space indent nests one level), "1. " lists.
  std::istringstream in(text);
  std::string l, o, para;
  int depth = 0;
  auto close_lists = [&](int to) {
    while (depth > to) {
      o += "</li></ul>\n";
      --depth;
    }
  };
  auto flush = [&] {
    if (!para.empty()) o += "<p>" + inline_html(trim(para)) + "</p>\n";
    para.clear();
  };
  while (std::getline(in, l)) {
    const std::size_t ind = l.find_first_not_of(' ');
    const std::string t = trim(l);
    if (starts(t, "- ") || starts(t, "* ")) {
      flush();
      const int want = int(ind / 2) + 1;
      if (want > depth) {
        while (depth < want) {
          o += "<ul><li>";
          ++depth;
        }
      } else {
        close_lists(want);
        o += "</li><li>";
      }
      o += inline_html(t.substr(2));
    } else if (depth > 0) {
      o += " " + inline_html(t);
    } else {
      para += t + " ";
    }
  }
  close_lists(0);
  flush();
  return o;
}

}  // namespace

std::string to_html(const Document& d) {
  std::string h = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>" +
                   html_escape(d.title) + "</title>\n<style>" + kStyle + "</style></head>\n<body><main>\n<h1>" + html_escape(d.title) + "</h1>\n";
  for (const auto& b : d.blocks) {
    switch (b.kind) {
      case Block::Kind::heading:
        h += fmt::format("<h{0}{1}>{2}</h{0}>\n", b.level, b.id.empty() ? "" : " id=\"" + b.id + "\"", inline_html(b.text));
        break;
      case Block::Kind::text:
        h += b.text.find("](#s") != std::string::npos && starts(b.text, "- [") ? "<nav class=\"toc\">" + html_text(b.text) + "</nav>\n"
                                                                                 : html_text(b.text);
        break;
      case Block::Kind::code: h += "<pre><code>" + html_escape(b.text) + "</code></pre>\n"; break;
      case Block::Kind::comment: break;
      case Block::Kind::table: {
        h += "<div class=\"tablewrap\"><table class=\"sortable\"><thead><tr>";
        for (std::size_t c = 0; c < b.table.head.size(); ++c)
          h += fmt::format("<th{}>{}</th>", c < b.table.align.size() && !b.table.align[c].empty() ? " class=\"" + b.table.align[c] + "\"" : "",
                           inline_html(b.table.head[c]));
        h += "</tr></thead>\n<tbody>\n";
        for (const auto& r : b.table.rows) {
          h += "<tr>";
          for (std::size_t c = 0; c < r.size(); ++c)
            h += fmt::format("<td{}>{}</td>", c < b.table.align.size() && !b.table.align[c].empty() ? " class=\"" + b.table.align[c] + "\"" : "",
                             inline_html(r[c]));
          h += "</tr>\n";
        }
        h += "</tbody></table></div>\n";
        break;
      }
      case Block::Kind::gallery:
        if (b.pictures.size() == 1 && b.pictures[0].thumb.empty()) {
          h += "<p><img src=\"" + html_escape(b.pictures[0].src) + "\" alt=\"" + html_escape(b.pictures[0].caption) + "\"></p>\n";
          break;
        }
        h += "<div class=\"grid\">\n";
        for (const auto& p : b.pictures)
          h += fmt::format("<figure><a href=\"{0}\"><img src=\"{1}\" alt=\"{2}\" loading=\"lazy\"></a><figcaption><code>{2}</code></figcaption></figure>\n",
                           html_escape(p.src), html_escape(p.thumb.empty() ? p.src : p.thumb), html_escape(p.caption));
        h += "</div>\n";
        break;
    }
  }
  h += "</main>\n<script>" + std::string(kScript) + "</script>\n</body></html>\n";
  return h;
}

std::vector<std::string> broken_links(const fs::path& html) {
  std::ifstream f(html);
  std::stringstream ss;
  ss << f.rdbuf();
  if (ss.str().empty()) return {html.string() + ": empty or unreadable"};
  return broken_links(ss.str(), html.parent_path());
}

std::vector<std::string> broken_links(const std::string& page, const fs::path& dir) {
  std::vector<std::string> bad;
  if (page.empty()) return {"the page is empty"};
  std::set<std::string> ids;
  static const std::regex id_re(R"re(\sid="([^"]+)")re");
  for (std::sregex_iterator it(page.begin(), page.end(), id_re), e; it != e; ++it) ids.insert((*it)[1]);
  static const std::regex ref_re(R"re(\s(src|href)="([^"]*)")re");
  for (std::sregex_iterator it(page.begin(), page.end(), ref_re), e; it != e; ++it) {
    std::string target = (*it)[2];
    for (const auto& [from, to] : {std::pair<std::string, std::string>{"&amp;", "&"}, {"&quot;", "\""}}) {
      for (std::size_t p; (p = target.find(from)) != std::string::npos;) target.replace(p, from.size(), to);
    }
    const std::string what = std::string((*it)[1]) + "=\"" + target + "\"";
    if (target.empty()) {
      bad.push_back(what + ": empty");
    } else if (target.find("://") != std::string::npos || starts(target, "//") || starts(target, "mailto:")) {
      bad.push_back(what + ": a network address (the page must stand alone)");
    } else if (target[0] == '#') {
      if (!ids.count(target.substr(1))) bad.push_back(what + ": no element with this id");
    } else {
      const std::string file = target.substr(0, target.find('#'));
      if (!fs::is_regular_file(dir / file)) bad.push_back(what + ": no such file beside the page");
    }
  }
  return bad;
}

}  // namespace rb::app::doc
