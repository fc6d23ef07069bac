#include "accuracy/common.hpp"

#include <regex>

namespace rb::acc {

bool selects(const std::string& filter, const std::string& family_case) {
  if (filter.empty()) return true;
  static thread_local std::string last;
  static thread_local std::regex re;
  if (filter != last) re = std::regex(filter, std::regex::extended | std::regex::nosubs), last = filter;
  return std::regex_search(family_case, re);
}

std::vector<CaseInfo> case_list(const TracerCases* tracer) {
  std::vector<CaseInfo> all;
  for (auto f : {triangle_cases, sphere_cases, quadric_cases, torus_cases, quartic_cases, box_cases, implicit_cases, secondary_cases}) {
    auto v = f();
    all.insert(all.end(), v.begin(), v.end());
  }
  if (tracer) {
    auto v = tracer->scene_cases();
    all.insert(all.end(), v.begin(), v.end());
  }
  return all;
}

std::vector<Row> run_lab(const Options& o) {
  std::vector<Row> rows;
  Ctx x;
  x.o = &o;
  x.rays = o.rays ? o.rays : (o.full ? 100000 : 10000);
  x.rows = &rows;
  x.cases_total = 0;
  for (const CaseInfo& c : case_list(o.tracer)) x.cases_total += x.selected(c.family, c.name);
  struct Fam {
    const char* name;
    void (*run)(Ctx&);
  };
  const Fam fams[] = {{"triangle", run_triangles}, {"sphere", run_spheres}, {"quadric", run_quadrics},
                      {"torus", run_torus},       {"quartic", run_quartics}, {"box", run_boxes},
                      {"implicit", run_implicit}, {"secondary", run_secondary}, {"scene", o.tracer ? o.tracer->run_scenes : nullptr}};
  for (const Fam& f : fams) {
    if (!f.run) continue;
    x.reseed(f.name, "");  // each case reseeds too (Ctx::reseed)
    f.run(x);
  }
  if (o.progress) o.progress(1.0, "done");
  return rows;
}

}  // namespace rb::acc
