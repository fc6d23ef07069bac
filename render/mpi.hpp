// Rendering across MPI ranks (built when CMake finds MPI): every rank renders the tiles
// t % size == rank, and rank 0 gathers the sample grid and the counts. A sample belongs to one
// tile and every other rank leaves it at zero, so the summing reduction adds only exact zeros:
// rank 0's image is bit for bit the single-process one.
#pragma once

#include "render/render.hpp"

namespace rb::render {

// MPI_Init when the process was started by an MPI launcher (mpirun sets OMPI_COMM_WORLD_SIZE or
// PMI_SIZE), MPI_Finalize at the end; otherwise nothing, and rank 0 of 1.
class MpiSession {
 public:
  MpiSession(int* argc, char*** argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }
  bool active() const { return active_; }
  void barrier() const;

 private:
  int rank_ = 0, size_ = 1;
  bool active_ = false;
};

// Renders this rank's tiles and gathers everything on rank 0: `samples` holds the whole grid on
// rank 0 (other ranks: their own tiles only) and the returned counts are the sums over all ranks
// on rank 0 (other ranks: their own).
RenderStats render_tiles_mpi(const MpiSession& mpi, const Renderer& r, std::vector<float>& samples, int threads,
                             const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace rb::render
