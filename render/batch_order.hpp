// The order a batch of the renderer's rays is traced in when it goes in packets of 8 or 16
// (render.cpp Renderer::trace): the traversal takes a packet's consecutive rays as one only when
// they share a direction octant, so a batch is reordered, and the hits go back to the batch's
// order before shading (the image does not depend on the order).
#pragma once

#include "core/ray.hpp"
#include "soa/rays.hpp"
#include "tracer/ray_order.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rb::render {

// The rays written into `soa` (padded to 8 lanes with invalid rays) ordered by direction octant and,
// with `group` (below `groups`), by group within an octant, stably: a generation interleaves
// reflection with refraction rays and each hit's shadow rays towards different lights (their group:
// rays to one light converge). `order` gets the order (slot -> batch index), empty when all share
// one bucket (then the batch's own order). `bucket` and `start` are scratch.
void octant_pack(const std::vector<Ray<float>>& rays, RaySoA& soa, std::vector<std::uint32_t>& order,
                 std::vector<std::uint32_t>& bucket, std::vector<std::size_t>& start, const std::uint32_t* group = nullptr,
                 std::size_t groups = 1);

// The rays written into `soa` (padded to 8 lanes with invalid rays); with `order`, ray order[i] into
// slot i.
void fill(RaySoA& soa, const std::vector<Ray<float>>& rays, const std::uint32_t* order = nullptr);

// The rays' indices ordered by the ray sort's key (octant, then the Morton codes of origin and
// direction), equal keys in the batch's order (by octant alone for batches of 2^28 rays or more).
// `keys` is scratch.
void key_order(const std::vector<Ray<float>>& rays, const tracer::RayKey& key, std::vector<std::uint64_t>& keys,
               std::vector<std::uint32_t>& order);

}  // namespace rb::render
