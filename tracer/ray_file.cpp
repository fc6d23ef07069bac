#include "tracer/ray_file.hpp"

#include "core/output_file.hpp"

#include <nlohmann/json.hpp>

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <stdexcept>

namespace rb::tracer {

namespace {

using nlohmann::json;

static_assert(std::endian::native == std::endian::little, "ray files are little-endian float32, as this machine");

constexpr const char* kMagic = "raybench rays 1";
constexpr std::size_t kFloatsPerRay = 8;
constexpr std::size_t kBytesPerRay = kFloatsPerRay * sizeof(float);
constexpr std::size_t kMaxHeader = std::size_t(1) << 20;

[[noreturn]] void fail(const std::string& path, const std::string& why) { throw std::runtime_error(path + ": " + why); }

// A ray as written: the stored fields when they keep the ray contract (unit direction, rd = 1/d,
// an ordered finite interval: the render's rays, bit for bit), the contract's invalid ray when the
// interval is empty, and otherwise the ray made again from its origin, direction and interval.
Ray<float> ray_from(const float* v) {
  const Vec3f o{v[0], v[1], v[2]}, d{v[3], v[4], v[5]};
  const float tmin = v[6], tmax = v[7];
  const double len = std::sqrt(double(d.x) * double(d.x) + double(d.y) * double(d.y) + double(d.z) * double(d.z));
  const bool kept = finite3(o) && finite3(d) && std::fabs(len - 1.0) <= 1e-6 && std::isfinite(tmin) && std::isfinite(tmax) &&
                    tmin <= tmax;
  if (!kept) return make_ray(o, d, tmin, tmax);
  return {o, d, {1.0f / d.x, 1.0f / d.y, 1.0f / d.z}, tmin, tmax};
}

}  // namespace

std::string RaySection::label() const { return "generation " + std::to_string(generation) + " " + kind; }

std::size_t RayFile::rays() const {
  std::size_t n = 0;
  for (const auto& s : sections) n += s.rays.size();
  return n;
}

void write_ray_file(const std::string& path, const RayFile& f) {
  json sections = json::array();
  for (const auto& s : f.sections)
    sections.push_back({{"kind", s.kind}, {"generation", s.generation}, {"query", s.any ? "any" : "closest"}, {"packet", s.packet},
                        {"rays", s.rays.size()}});
  const json header{{"scene", f.scene}, {"model", f.model}, {"origin", {f.origin.x, f.origin.y, f.origin.z}}, {"sections", sections}};
  std::string out = std::string(kMagic) + "\n" + header.dump() + "\n";
  const std::size_t at = out.size();
  out.resize(at + f.rays() * kBytesPerRay);
  char* p = out.data() + at;
  for (const auto& s : f.sections)
    for (const auto& r : s.rays) {
      const float v[kFloatsPerRay] = {r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z, r.tmin, r.tmax};
      std::memcpy(p, v, kBytesPerRay);
      p += kBytesPerRay;
    }
  write_output(path, out);
}

bool is_ray_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  return in && std::getline(in, line) && line == kMagic;
}

RayFile read_ray_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, std::string("cannot be read: ") + std::strerror(errno));
  std::string line;
  if (!std::getline(in, line) || line != kMagic) fail(path, std::string("line 1: not a ray file (it does not start with \"") + kMagic + "\")");
  std::string head;
  for (char c; in.get(c) && c != '\n';) {
    head.push_back(c);
    if (head.size() > kMaxHeader) fail(path, "line 2: the header runs over 1 MiB");
  }
  if (!in) fail(path, "line 2: the file ends inside the header");
  RayFile f;
  json h;
  try {
    h = json::parse(head);
    f.scene = h.at("scene").get<std::string>();
    f.model = h.at("model").get<std::string>();
    const auto& o = h.at("origin");
    if (!o.is_array() || o.size() != 3) throw std::runtime_error("\"origin\" is not three numbers");
    f.origin = {o[0].get<double>(), o[1].get<double>(), o[2].get<double>()};
    if (!finite3(f.origin)) throw std::runtime_error("\"origin\" is not finite");
  } catch (const std::exception& e) {
    fail(path, std::string("line 2: the header is not a ray file's: ") + e.what());
  }
  in.seekg(0, std::ios::end);
  const std::size_t end = std::size_t(in.tellg());
  std::size_t pos = line.size() + 1 + head.size() + 1;
  in.seekg(std::streamoff(pos));
  const json& secs = h.contains("sections") && h["sections"].is_array() ? h["sections"] : json::array();
  if (secs.empty()) fail(path, "line 2: the header lists no sections");
  for (std::size_t k = 0; k < secs.size(); ++k) {
    RaySection s;
    std::size_t n = 0;
    const std::string where = "line 2: section " + std::to_string(k + 1);
    try {
      s.kind = secs[k].at("kind").get<std::string>();
      s.generation = secs[k].at("generation").get<int>();
      const std::string q = secs[k].at("query").get<std::string>();
      s.packet = secs[k].at("packet").get<int>();
      n = secs[k].at("rays").get<std::size_t>();
      if (s.kind != "eye" && s.kind != "secondary" && s.kind != "shadow") throw std::runtime_error("kind \"" + s.kind + "\" is not eye, secondary or shadow");
      if (q != "any" && q != "closest") throw std::runtime_error("query \"" + q + "\" is not closest or any");
      if (s.packet != 1 && s.packet != 8 && s.packet != 16 && s.packet != 64) throw std::runtime_error("packet is not 1, 8, 16 or 64");
      if (s.generation < 1 || s.generation > 64) throw std::runtime_error("generation is outside 1 .. 64");
      s.any = q == "any";
    } catch (const std::exception& e) {
      fail(path, where + ": " + e.what());
    }
    // The count checked against the bytes left before anything is allocated.
    if (n > (end - pos) / kBytesPerRay)
      fail(path, where + " (" + s.label() + ") promises " + std::to_string(n) + " rays; only " +
                     std::to_string((end - pos) / kBytesPerRay) + " follow");
    std::vector<float> v(n * kFloatsPerRay);
    if (n && !in.read(reinterpret_cast<char*>(v.data()), std::streamsize(n * kBytesPerRay))) fail(path, where + ": read failed");
    s.rays.reserve(n);
    for (std::size_t i = 0; i < n; ++i) s.rays.push_back(ray_from(&v[kFloatsPerRay * i]));
    pos += n * kBytesPerRay;
    f.sections.push_back(std::move(s));
  }
  if (pos != end) fail(path, std::to_string(end - pos) + " bytes follow the last section's rays");
  return f;
}

void move_frame(RayFile& f, const Vec3d& to) {
  if (f.origin.x == to.x && f.origin.y == to.y && f.origin.z == to.z) return;
  const Vec3d shift = f.origin - to;
  for (auto& s : f.sections)
    for (auto& r : s.rays)
      if (r.tmin <= r.tmax) r = make_ray(to_double(r.o) + shift, to_double(r.d), double(r.tmin), double(r.tmax));
  f.origin = to;
}

}  // namespace rb::tracer
