// Reading the JSON scene format (internal to scene/): values at a JSON path with an error that
// names the path ("objects[2].radius: expected a positive number"; the caller prefixes the file),
// and what the scene reader (scene/json_scene.cpp) asks of the CSG builder (scene/csg_scene.cpp).
#pragma once

#include "scene/scene.hpp"
#include "core/suggest.hpp"
#include "core/vec3.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace rb::scene::json_read {
using nlohmann::json;

// An error at a JSON path; the caller prefixes the file name.
struct PathError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
[[noreturn]] inline void fail(const std::string& path, const std::string& what) { throw PathError(path + ": " + what); }
inline std::string key_path(const std::string& path, const char* key) { return path.empty() ? std::string(key) : path + "." + key; }

inline const json& need(const json& j, const std::string& path, const char* key) {
  if (!j.contains(key)) fail(key_path(path, key), "missing");
  return j[key];
}
inline double number(const json& v, const std::string& path) {
  if (!v.is_number()) fail(path, "expected a number");
  const double x = v.get<double>();
  if (!std::isfinite(x)) fail(path, "expected a finite number");
  return x;
}
inline double num(const json& j, const std::string& path, const char* key) { return number(need(j, path, key), key_path(path, key)); }
inline double positive(const json& j, const std::string& path, const char* key) {
  const json& v = need(j, path, key);
  if (!v.is_number() || !std::isfinite(v.get<double>()) || !(v.get<double>() > 0)) fail(key_path(path, key), "expected a positive number");
  return v.get<double>();
}
inline Vec3d vec3(const json& v, const std::string& path) {
  if (!v.is_array() || v.size() != 3) fail(path, "expected an array of three numbers");
  return {number(v[0], path + "[0]"), number(v[1], path + "[1]"), number(v[2], path + "[2]")};
}
inline Vec3d vec(const json& j, const std::string& path, const char* key) { return vec3(need(j, path, key), key_path(path, key)); }
inline Vec3d nonzero(const json& j, const std::string& path, const char* key) {
  const Vec3d v = vec(j, path, key);
  if (!(dot(v, v) > 0)) fail(key_path(path, key), "expected a non-zero vector");
  return v;
}

// Refuses a key of object j that is not one of `keys`, naming the nearest one: a misspelt key
// ("trnsform", "colour") would otherwise be dropped without a word.
inline void only_keys(const json& j, const std::string& path, const std::vector<std::string>& keys) {
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (std::find(keys.begin(), keys.end(), it.key()) != keys.end()) continue;
    std::string list;
    for (const auto& k : keys) list += (list.empty() ? "" : ", ") + k;
    fail(path.empty() ? it.key() : path + "." + it.key(), "unknown key (" + list + ")" + did_you_mean(it.key(), keys));
  }
}

// The material a node names ("material"), else `inherited`; names resolved through `materials`
// (null: not resolved, the inherited one kept). scene/csg_scene.cpp.
std::uint32_t node_material(const json& node, const std::string& path, const std::map<std::string, std::uint32_t>* materials,
                            std::uint32_t inherited);
// The CSG tree of a node placed by M, its leaves' material `mat` unless they name one.
CsgTree csg_tree(const json& node, const std::string& path, const Affine3d& M, const std::map<std::string, std::uint32_t>* materials,
                 std::uint32_t mat);

}  // namespace rb::scene::json_read
