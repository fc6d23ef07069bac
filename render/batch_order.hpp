// The order a batch of the renderer's rays is traced in when it goes in packets of 8 or 16
// (render.cpp Renderer::trace): the traversal takes a packet's consecutive rays as one only when
// they share a direction octant, so a batch is reordered, and the hits go back to the batch's
// order before shading (the image does not depend on the order).
#pragma once

#include "core/ray.hpp"
#include "tracer/ray_order.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rb::render {

// The rays' indices ordered by direction octant and, with `group` (below `groups`), by group within
// an octant, stably: a generation interleaves reflection with refraction rays and each hit's shadow
// rays towards different lights (their group: rays to one light converge). Empty when all share one
// bucket. `count` is scratch.
void octant_order(const std::vector<Ray<float>>& rays, std::vector<std::uint32_t>& order, std::vector<std::size_t>& count,
                  const std::uint32_t* group = nullptr, std::size_t groups = 1);

// The rays' indices ordered by the ray sort's key (octant, then the Morton codes of origin and
// direction), equal keys in the batch's order. `keys` is scratch.
void key_order(const std::vector<Ray<float>>& rays, const tracer::RayKey& key, std::vector<std::uint64_t>& keys,
               std::vector<std::uint32_t>& order);

}  // namespace rb::render
