// Rays kept in a file: the rays a render traced (`raybench render --rays-out FILE`), read back by
// `raybench trace SCENE --rays FILE`, which traces them alone (the render's shading, packing and
// bookkeeping left out).
//
// A file holds sections, each one batch of rays traced alike: a generation's eye or secondary rays
// (closest hit) or its shadow rays (any hit when the scene is opaque; closest hit past
// transmitting occluders otherwise), with the packet size the render traced them in, in the order
// it traced them. Rays are in the frame of the plan that traced them (`origin`, world coordinates
// of the frame's zero): read under a plan with another origin, they are moved to its frame in
// double.
//
// Layout: the line "raybench rays 1", a line of JSON (scene, model, origin, the sections with their
// ray counts), then per section its rays as little-endian float32: o.x o.y o.z d.x d.y d.z tmin tmax.
#pragma once

#include "core/ray.hpp"
#include "core/vec3.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace rb::tracer {

struct RaySection {
  std::string kind = "eye";  // eye | secondary | shadow
  int generation = 1;        // 1: the eye rays and their shadow rays
  bool any = false;          // any-hit queries (shadow rays of an opaque scene)
  int packet = 1;            // rays per packet as the render traced them (1, 8, 16 or 64)
  std::vector<Ray<float>> rays;
  std::string label() const;  // "generation 2 shadow"
};

struct RayFile {
  std::string scene, model;
  Vec3d origin{0, 0, 0};
  std::vector<RaySection> sections;
  std::size_t rays() const;
};

// Throws std::runtime_error naming the file when it cannot be written.
void write_ray_file(const std::string& path, const RayFile& f);
// Throws std::runtime_error "PATH: what is wrong" for a file that is not one, is truncated, or
// whose header is malformed or promises more rays than the file holds. A ray that breaks the ray
// contract (NaN, zero direction, ...) is read as the contract's invalid ray: a defined miss.
RayFile read_ray_file(const std::string& path);
// True when the file starts like a ray file (what `trace --rays` tells from a ray set's name).
bool is_ray_file(const std::string& path);

// The rays moved from the frame at `from` to the frame at `to` (world origins), in double; the
// same rays when the two are equal.
void move_frame(RayFile& f, const Vec3d& to);

}  // namespace rb::tracer
