// The report as a document model, written twice from the one model: report/index.md and a
// self-contained report/index.html (images beside it, charts as PNG, tables that sort by a small
// inline script, no network).
//
// The report's sections assemble markdown (apps/report*.cpp); parse_markdown reads that subset
// (headings, paragraphs, lists, fenced code, pipe tables, images, HTML comments) into blocks;
// organise numbers the sections, puts the summary of every goal and a table of contents at the
// top, turns runs of images into a thumbnail grid and moves long tables into an appendix; the two
// writers only render blocks.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace rb::app::doc {

struct Table {
  std::vector<std::string> head;
  std::vector<std::string> align;  // per column: "", "left", "right", "center"
  std::vector<std::vector<std::string>> rows;
};

struct Picture {
  std::string caption, src, thumb;  // thumb: a small copy beside the page ("" when none)
};

struct Block {
  enum class Kind { heading, text, table, gallery, code, comment };
  Kind kind = Kind::text;
  int level = 0;     // heading: 1..4
  std::string text;  // heading title; text: markdown paragraphs and lists; code; comment
  std::string id;    // heading anchor
  Table table;
  std::vector<Picture> pictures;  // gallery
};

// One goal of the report, checked in this run. met: 1 yes, 0 no, -1 not measured.
// A goal's verdict: met, not met, undecided (its ratio's 95 % interval straddles the target) or not
// measured, as the `met` codes of the report's JSON.
inline constexpr int kGoalNotMeasured = -1, kGoalNotMet = 0, kGoalMet = 1, kGoalUndecided = 2;
inline const char* goal_word(int met) {
  return met == kGoalMet ? "met" : met == kGoalNotMet ? "not met" : met == kGoalUndecided ? "undecided" : "not measured";
}
// A goal over rows (cases, scenes, methods), from how many there are, how many met it and how many
// fell below it: not met when one fell below, met when every one met it, undecided otherwise; not
// measured without rows.
inline int goal_over(std::size_t rows, std::size_t met, std::size_t below) {
  return rows == 0 ? kGoalNotMeasured : below ? kGoalNotMet : met == rows ? kGoalMet : kGoalUndecided;
}
// The same in a table's "met" column (markdown).
inline const char* goal_cell(int met) {
  return met == kGoalMet ? "yes" : met == kGoalNotMet ? "**no**" : met == kGoalUndecided ? "undecided" : "-";
}

struct Goal {
  std::string section;  // the start of the title of the section that measures it
  std::string goal, measured;
  int met = kGoalNotMeasured;  // kGoal*
  std::string figure;  // a PNG beside the page that shows it ("" when none)
};

struct Document {
  std::string title;
  std::vector<Block> blocks;
};

Document parse_markdown(const std::string& md);

struct OrganiseOptions {
  std::size_t appendix_rows = 30;  // tables with more rows go to the appendix
  int thumb_width = 192;           // pixels; thumbnails go to OUT/thumbs/
  std::size_t gallery_min = 3;     // this many images in a row become a grid
};
// `out` is the folder the page is written to (thumbnails are made there).
void organise(Document& d, const std::vector<Goal>& goals, const std::filesystem::path& out, const OrganiseOptions& o = {});

std::string to_markdown(const Document& d);
std::string to_html(const Document& d);

// A PNG scaled to `width` pixels wide (height in proportion), written as PNG; false with the
// reason in `why` when the image cannot be read or written.
bool make_thumbnail(const std::filesystem::path& png, const std::filesystem::path& thumb, int width, std::string* why);

// Every image source and link target of an HTML page that does not resolve: a file missing
// beside the page, an anchor with no element of that id, or a network address (the page must
// stand alone). One line per problem; empty when the page is whole.
std::vector<std::string> broken_links(const std::filesystem::path& html);
// The same for a page in memory whose relative links resolve in `dir` (the page just written: its
// path may be a FIFO or a device, which cannot be read back).
std::vector<std::string> broken_links(const std::string& page, const std::filesystem::path& dir);

}  // namespace rb::app::doc
