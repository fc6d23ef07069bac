#include "accuracy/common.hpp"

namespace rb::acc {

std::vector<CaseInfo> case_list() {
  std::vector<CaseInfo> all;
  for (auto f : {triangle_cases, sphere_cases, quadric_cases, torus_cases, box_cases, secondary_cases}) {
    auto v = f();
    all.insert(all.end(), v.begin(), v.end());
  }
  return all;
}

std::vector<Row> run_lab(const Options& o) {
  std::vector<Row> rows;
  Ctx x{&o, o.rays ? o.rays : (o.full ? 20000 : 2000), std::mt19937_64(o.seed), &rows};
  struct Fam {
    const char* name;
    void (*run)(Ctx&);
    double weight;  // share of the run time, for the progress bar
  };
  const Fam fams[] = {{"triangle", run_triangles, 0.3}, {"sphere", run_spheres, 0.15}, {"quadric", run_quadrics, 0.15},
                      {"torus", run_torus, 0.2},       {"box", run_boxes, 0.1},        {"secondary", run_secondary, 0.1}};
  double done = 0;
  for (const Fam& f : fams) {
    if (o.progress) o.progress(done, f.name);
    x.rng.seed(o.seed * 1000003ULL + std::hash<std::string>{}(f.name));  // each family reproducible on its own
    f.run(x);
    done += f.weight;
  }
  if (o.progress) o.progress(1.0, "done");
  return rows;
}

}  // namespace rb::acc
