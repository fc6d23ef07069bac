// The report's HTML writer (apps/report_doc.hpp): one self-contained page from the document model
// (inline style, a small script that sorts tables and logs undecodable images), and the check of its
// links.
#include "apps/report/report_doc.hpp"
#include "core/text.hpp"

#include <fmt/format.h>

#include <cctype>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

namespace rb::app::doc {

namespace fs = std::filesystem;

namespace {

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
    if (!para.empty()) o += "<p>" + inline_html(rb::trim(para)) + "</p>\n";
    para.clear();
  };
  while (std::getline(in, l)) {
    const std::size_t ind = l.find_first_not_of(' ');
    const std::string t = rb::trim(l);
    if (t.starts_with("- ") || t.starts_with("* ")) {
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
        h += b.text.find("](#s") != std::string::npos && b.text.starts_with("- [") ? "<nav class=\"toc\">" + html_text(b.text) + "</nav>\n"
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
    } else if (target.find("://") != std::string::npos || target.starts_with("//") || target.starts_with("mailto:")) {
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
