// `cmake --install`: raybench and what it reads at run time (the chart scripts, the embedded
// meshes) under a prefix, and the installed binary finding them relative to its own path when run
// from another folder (apps/paths.hpp).
#include "cli_test_util.hpp"

#include <gtest/gtest.h>

namespace {

using namespace rbtest;

TEST(Install, InstalledBinaryFindsItsShareFolderFromAnyFolder) {
  Scratch s("install");
  const std::string prefix = s / "prefix";
  const std::string cmd = std::string("'") + RB_CMAKE_COMMAND + "' --install '" + RB_BINARY_DIR + "' --prefix '" + prefix + "' >'" +
                          (s / "install.log") + "' 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp(s / "install.log");
  const fs::path bin = fs::path(prefix) / "bin" / "raybench", share = fs::path(prefix) / "share" / "raybench";
  ASSERT_TRUE(fs::exists(bin));
  for (const char* f : {"tools/charts.py", "tools/accuracy_charts.py", "tools/history_plot.py", "data/meshes/stanford-bunny.obj"})
    EXPECT_TRUE(fs::exists(share / f)) << f;

  fs::create_directories(s / "elsewhere");
  const fs::path cwd = s / "elsewhere";
  Outcome r = run_in(cwd, "--version", "", "", bin.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(has(r.out, "data and tools " + fs::weakly_canonical(share).string())) << r.out;

  // The installed chart script draws for the installed binary.
  const std::string bench = "bench --filter '^box/slab/scalar/hit$' -r 2 --min-time 0.001 --history h.sqlite";
  ASSERT_EQ(run_in(cwd, bench, "", "", bin.string()).status, 0);
  ASSERT_EQ(run_in(cwd, bench, "", "", bin.string()).status, 0);
  r = run_in(cwd, "history --history h.sqlite --metric tests_per_s --plot p.png", "", "", bin.string());
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(slurp(cwd / "p.png").substr(1, 3), "PNG");
  // The embedded meshes the report reads are there for it.
  r = run_in(cwd, "info '" + (share / "data/meshes/stanford-bunny.obj").string() + "'", "", "", bin.string());
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(has(r.out, "69451")) << r.out;
}

}  // namespace
