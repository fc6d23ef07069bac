// The report's document model and its markdown writer (apps/report_doc.hpp; the HTML writer is
// apps/report_html.cpp).
#include "apps/report/report_doc.hpp"
#include "core/text.hpp"

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


// The cells of a pipe-table row: split at '|' outside code spans, "\|" kept as '|'.
std::vector<std::string> cells(const std::string& line) {
  std::string s = rb::trim(line);
  if (s.starts_with("|")) s.erase(0, 1);
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
      out.push_back(rb::trim(cur));
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(rb::trim(cur));
  return out;
}

// "![alt](src)" alone on a line: the image's alt and source.
bool image_line(const std::string& line, std::string& alt, std::string& src) {
  static const std::regex re(R"(^!\[([^\]]*)\]\(([^)\s]+)\)$)");
  std::smatch m;
  const std::string t = rb::trim(line);
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

std::string strip_number(const std::string& title) {
  static const std::regex re(R"(^\d+(\.\d+)*\.?\s+)");
  return std::regex_replace(title, re, "");
}

// A caption line before an image: "`name`" alone.
bool caption_line(const std::string& text, std::string& cap) {
  const std::string t = rb::trim(text);
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
    if (!rb::trim(para).empty()) d.blocks.push_back({Block::Kind::text, 0, rb::trim(para), "", {}, {}});
    para.clear();
  };
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string& l = lines[i];
    const std::string t = rb::trim(l);
    if (t.starts_with("```")) {
      flush();
      std::string code;
      for (++i; i < lines.size() && !rb::trim(lines[i]).starts_with("```"); ++i) code += lines[i] + "\n";
      d.blocks.push_back({Block::Kind::code, 0, code, "", {}, {}});
      continue;
    }
    if (t.starts_with("<!--")) {
      flush();
      d.blocks.push_back({Block::Kind::comment, 0, t, "", {}, {}});
      continue;
    }
    if (t.starts_with("#")) {
      std::size_t n = 0;
      while (n < t.size() && t[n] == '#') ++n;
      if (n <= 4 && n < t.size() && t[n] == ' ') {
        flush();
        if (n == 1 && d.title.empty()) d.title = rb::trim(t.substr(n));
        else d.blocks.push_back({Block::Kind::heading, int(n), rb::trim(t.substr(n)), "", {}, {}});
        continue;
      }
    }
    if (t.starts_with("|") && i + 1 < lines.size() && rb::trim(lines[i + 1]).starts_with("|") && rb::trim(lines[i + 1]).find("---") != std::string::npos) {
      flush();
      Block b{Block::Kind::table, 0, "", "", {}, {}};
      b.table.head = cells(t);
      for (const auto& a : cells(lines[i + 1])) {
        const bool l0 = a.starts_with(":"), r0 = !a.empty() && a.back() == ':';
        b.table.align.push_back(l0 && r0 ? "center" : r0 ? "right" : l0 ? "left" : "");
      }
      for (i += 2; i < lines.size() && rb::trim(lines[i]).starts_with("|"); ++i) {
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

namespace {
// A run of images (each with an optional caption line before it) becomes one grid of thumbnails
// (written to out/thumbs) once it has at least o.gallery_min images.
void make_galleries(Document& d, const fs::path& out, const OrganiseOptions& o) {
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
}  // namespace

void organise(Document& d, const std::vector<Goal>& goals, const fs::path& out, const OrganiseOptions& o) {
  // 1. Galleries.
  make_galleries(d, out, o);
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
        if (bare.starts_with(g.section.c_str()))
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

}  // namespace rb::app::doc
