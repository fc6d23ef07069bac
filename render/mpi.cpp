#include "render/mpi.hpp"

#include <mpi.h>

#include <cstdlib>
#include <stdexcept>

namespace rb::render {

MpiSession::MpiSession(int* argc, char*** argv) {
  if (!std::getenv("OMPI_COMM_WORLD_SIZE") && !std::getenv("PMI_SIZE")) return;
  int inited = 0;
  MPI_Initialized(&inited);
  if (!inited && MPI_Init(argc, argv) != MPI_SUCCESS) throw std::runtime_error("MPI_Init failed");
  active_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() {
  if (!active_) return;
  int fin = 0;
  MPI_Finalized(&fin);
  if (!fin) MPI_Finalize();
}

void MpiSession::barrier() const {
  if (active_) MPI_Barrier(MPI_COMM_WORLD);
}

RenderStats render_tiles_mpi(const MpiSession& mpi, const Renderer& r, std::vector<float>& samples, int threads,
                             const std::function<void(std::size_t, std::size_t)>& progress) {
  RenderStats st = render_tiles(r, samples, threads, mpi.rank(), mpi.size(), progress);
  if (!mpi.active() || mpi.size() == 1) return st;
  // Samples: a sum in which each sample has one non-zero term (x + 0 == x exactly).
  std::vector<float> all(mpi.rank() == 0 ? samples.size() : 0);
  if (samples.size() > std::size_t(INT32_MAX)) throw std::invalid_argument("image too large for one MPI reduction");
  MPI_Reduce(samples.data(), mpi.rank() == 0 ? all.data() : nullptr, int(samples.size()), MPI_FLOAT, MPI_SUM, 0,
             MPI_COMM_WORLD);
  if (mpi.rank() == 0) samples.swap(all);
  // Counts.
  std::vector<std::uint64_t> c = {st.eye, st.eye_hit, st.reflect, st.refract, st.shadow, st.cost.nodes, st.cost.boxes, st.cost.prims};
  for (int k = 0; k < bvh::kMaxKinds; ++k) c.push_back(st.cost.kind_prims[k]);
  std::vector<std::uint64_t> sum(c.size());
  MPI_Reduce(c.data(), sum.data(), int(c.size()), MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
  if (mpi.rank() == 0) {
    st.eye = sum[0]; st.eye_hit = sum[1]; st.reflect = sum[2]; st.refract = sum[3]; st.shadow = sum[4];
    st.cost.nodes = sum[5]; st.cost.boxes = sum[6]; st.cost.prims = sum[7];
    for (int k = 0; k < bvh::kMaxKinds; ++k) st.cost.kind_prims[k] = sum[8 + std::size_t(k)];
  }
  return st;
}

}  // namespace rb::render
