// The report's document model (apps/report_doc.hpp) on a small report of its own: numbered
// sections, the summary of goals and the contents at the top, images in a row as a thumbnail grid
// (thumbnails made and small), long tables in the appendix, and every image and link of the HTML
// page resolving; a missing file, a missing anchor and a network address are each found.
#include "apps/report/report_doc.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;
using namespace rb::app;

namespace {

// Width and height from a PNG's IHDR chunk.
std::pair<std::uint32_t, std::uint32_t> png_size(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  unsigned char h[24] = {};
  f.read(reinterpret_cast<char*>(h), 24);
  auto be = [&](int o) { return std::uint32_t(h[o]) << 24 | std::uint32_t(h[o + 1]) << 16 | std::uint32_t(h[o + 2]) << 8 | h[o + 3]; };
  return {be(16), be(20)};
}

}  // namespace

// Outside the anonymous namespace: the TEST_F classes derive from it (GCC's -Wsubobject-linkage).
struct SmallReport : ::testing::Test {
  fs::path dir = fs::temp_directory_path() / ("rb_report_doc_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                                               ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::string md;
  void SetUp() override {
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path png = fs::path(RB_TEST_DATA) / "render" / "reflection.png";
    for (const char* n : {"render_a.png", "render_b.png", "render_c.png", "chart.png"}) fs::copy_file(png, dir / n);
    md = "# raybench report\n\nProduced by a test.\n\n## Machine and build\n\n| key | value |\n|---|---|\n| cpu | test |\n\n"
         "## 2. Scalar against SIMD\n\nText with `code`, **bold** and a [link](chart.png).\n\n"
         "| kernel | speedup |\n|---|---:|\n";
    for (int i = 0; i < 40; ++i) md += "| k" + std::to_string(i) + " | " + std::to_string(40 - i) + ".0x |\n";
    md += "\n![SIMD speedup](chart.png)\n\n### Goals\n\n- one\n- two\n\n## Rendering: the ray tracer\n\n### Images\n\n";
    for (const char* n : {"a", "b", "c"}) md += std::string("`scene ") + n + "`\n\n![scene](render_" + n + ".png)\n\n";
    md += "<!-- pgo-section -->\n## Profile-guided optimisation\n\nNot measured.\n<!-- /pgo-section -->\n";
  }
  void TearDown() override { fs::remove_all(dir); }
  doc::Document organised() {
    doc::Document d = doc::parse_markdown(md);
    const std::vector<doc::Goal> goals = {{"Scalar against SIMD", "SIMD >= 6x", "5.1x", 0, "chart.png"},
                                          {"Rendering", "half of primary", "3 of 3", 1, ""},
                                          {"Nowhere", "not measured", "-", -1, ""}};
    doc::OrganiseOptions o;
    o.thumb_width = 16;  // below the test image's width, so that the thumbnail is scaled down
    doc::organise(d, goals, dir, o);
    return d;
  }
};

TEST_F(SmallReport, SectionsAreNumberedWithTheSummaryAndContentsFirst) {
  const doc::Document d = organised();
  EXPECT_EQ(d.title, "raybench report");
  std::vector<std::string> h2;
  for (const auto& b : d.blocks)
    if (b.kind == doc::Block::Kind::heading && b.level == 2) h2.push_back(b.text);
  ASSERT_GE(h2.size(), 6u);
  EXPECT_EQ(h2[0], "Summary: the goals");
  EXPECT_EQ(h2[1], "Contents");
  EXPECT_EQ(h2[2], "1. Machine and build");
  EXPECT_EQ(h2[3], "2. Scalar against SIMD");  // its own number replaced, not doubled
  EXPECT_EQ(h2[4], "3. Rendering: the ray tracer");
  EXPECT_EQ(h2[5], "4. Profile-guided optimisation");
  EXPECT_EQ(h2.back(), "Appendix A. Long tables");
  const std::string text = doc::to_markdown(d);
  EXPECT_NE(text.find("3 goals: **1 met**, **1 not met**, 1 not measured"), std::string::npos) << text;
  EXPECT_NE(text.find("| SIMD >= 6x | 5.1x | **no** | [chart](chart.png) | [2. Scalar against SIMD](#s2-scalar-against-simd) |"),
            std::string::npos) << text;
  EXPECT_NE(text.find("- [3. Rendering: the ray tracer](#s3-rendering-the-ray-tracer)"), std::string::npos);
  EXPECT_NE(text.find("  - [3.1 Images](#s3-1-images)"), std::string::npos);
  EXPECT_NE(text.find("<!-- pgo-section -->"), std::string::npos);  // ./run.sh pgo still finds its markers
}

TEST_F(SmallReport, LongTablesGoToTheAppendixAndImagesInARowToAGrid) {
  const doc::Document d = organised();
  const std::string text = doc::to_markdown(d);
  EXPECT_NE(text.find("(40 rows) is in [Appendix A.1](#appendix-1)"), std::string::npos) << text;
  EXPECT_LT(text.find("Appendix A.1]"), text.find("### A.1 2. Scalar against SIMD"));
  EXPECT_NE(text.find("[![scene b](thumbs/render_b.png)](render_b.png)"), std::string::npos) << text;
  for (const char* n : {"render_a.png", "render_b.png", "render_c.png"}) {
    ASSERT_TRUE(fs::exists(dir / "thumbs" / n)) << n;
    const auto [w, h] = png_size(dir / "thumbs" / n);
    const auto [W, H] = png_size(dir / n);
    ASSERT_GT(W, 16u);
    EXPECT_EQ(w, 16u);
    EXPECT_NEAR(double(h) / w, double(H) / W, 0.07);
  }
  // The single chart stays a plain image.
  EXPECT_NE(text.find("![SIMD speedup](chart.png)"), std::string::npos);
}

TEST_F(SmallReport, EveryImageAndLinkOfThePageResolvesAndBreakagesAreFound) {
  const doc::Document d = organised();
  const std::string html = doc::to_html(d);
  std::ofstream(dir / "index.html") << html;
  EXPECT_EQ(doc::broken_links(dir / "index.html"), std::vector<std::string>{});
  EXPECT_NE(html.find("<table class=\"sortable\">"), std::string::npos);
  EXPECT_NE(html.find("<img src=\"thumbs/render_a.png\""), std::string::npos);
  EXPECT_NE(html.find("<strong>bold</strong>"), std::string::npos);
  EXPECT_EQ(html.find("http"), std::string::npos) << "the page must stand alone";
  fs::remove(dir / "thumbs" / "render_c.png");
  std::ofstream(dir / "index.html") << html << "<a href=\"#nowhere\">x</a><img src=\"https://example.org/x.png\">";
  const auto bad = doc::broken_links(dir / "index.html");
  ASSERT_EQ(bad.size(), 3u);
  EXPECT_NE(bad[0].find("thumbs/render_c.png"), std::string::npos) << bad[0];
  EXPECT_NE(bad[1].find("#nowhere"), std::string::npos) << bad[1];
  EXPECT_NE(bad[2].find("network"), std::string::npos) << bad[2];
}
