// Every option a kind's plan can choose (K::plan in tracer/kinds/*.hpp) cites the lab cases on
// which it has no failure; check_plan_evidence runs each cited case (the lab's own seed and
// generators, 2000 rays) and expects the option's method to show no failure there, in every
// precision the tracer runs it in: float and 8-lane SIMD for a float option (the tracer's leaves
// run 8 lanes; the scalar row is the same arithmetic), double for a double one.
// Without the lab's tracer cases (tracer == nullptr) the cases through the whole tracer (families
// "scene" and "bvh") are left out. Returns how many (option, case) pairs it checked.
#pragma once

#include "accuracy/lab.hpp"
#include "tracer/kinds.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

inline int check_plan_evidence(const rb::acc::TracerCases* tracer) {
  int checked = 0;
  rb::kinds::AllKinds::each([&]<class K>() {
    for (const auto& o : K::plan) {
      std::istringstream cases(o.evidence);
      std::string c;
      while (cases >> c) {
        if (!tracer && (c.starts_with("scene/") || c.starts_with("bvh/"))) continue;
        rb::acc::Options lo;
        lo.filter = c;
        lo.rays = 2000;
        lo.timing = false;
        lo.tracer = tracer;
        const std::string method = K::methods.at(std::size_t(o.method)).name;
        int seen = 0;
        for (const rb::acc::Row& r : rb::acc::run_lab(lo)) {
          if (r.family + "/" + r.case_name != c || r.method != method) continue;
          if ((r.precision == "double") != o.f64) continue;
          ++seen;
          EXPECT_EQ(r.failure_ppm(), 0.0) << K::name << " " << r.method << " " << r.precision << " on " << c;
        }
        EXPECT_GE(seen, 1) << "no row of " << method << " for " << c;
        ++checked;
      }
    }
  });
  return checked;
}
