#pragma once
// The MPI world this process is one rank of (docs/distributed.md). MPI is optional at
// build time (CMake NNSHADE_MPI, auto-detected): without it, or when the binary is not
// started by an MPI launcher, the world is one rank and nothing calls MPI, so a plain
// `train-gan` behaves exactly as it did before MPI existed.
//
// Only standard MPI-3 calls (no Open MPI extensions), so the code builds against MPICH.
//
//   int main(int argc, char** argv) {
//     runs::Session mpi(argc, argv);            // MPI_Init when launched by mpirun/srun
//     return mpi.finish(apps::run_main(...));    // MPI_Finalize, or MPI_Abort on failure
//   }
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#ifdef NNSHADE_MPI
#include <mpi.h>
#endif

namespace nns::runs {

struct WorldInfo {
  int rank = 0, size = 1;
  bool mpi = false;  // MPI_Init was called (launched by an MPI launcher, MPI built in)
};
inline WorldInfo& world() {
  static WorldInfo w;
  return w;
}
inline int rank() { return world().rank; }
inline int size() { return world().size; }
// Rank 0 alone writes outputs, metrics and checkpoints; every rank reads them on resume.
inline bool writer() { return world().rank == 0; }

// --accumulate's default: at least one micro-batch per rank, so `mpirun -np N` with the
// default flags runs, and trains the weights of one process with --accumulate N.
inline int default_accumulate(int one_process_default) { return std::max(one_process_default, size()); }
inline void announce_accumulate(const char* app, int accumulate) {
  if (size() > 1 && writer())
    std::fprintf(stderr, "%s: %d MPI ranks, --accumulate %d: the same weights as one process with --accumulate %d\n",
                 app, size(), accumulate, accumulate);
}

// The number of processes an MPI launcher says it started, or 0 when none did: Open MPI's
// mpirun sets OMPI_COMM_WORLD_SIZE, MPICH's Hydra PMI_SIZE, Slurm's srun (PMIx) PMIX_RANK.
inline int launcher_size() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* s = std::getenv(v)) return std::max(1, std::atoi(s));
  if (std::getenv("PMIX_RANK")) return 1;  // srun: the size is asked from MPI itself
  return 0;
}

inline bool built_with_mpi() {
#ifdef NNSHADE_MPI
  return true;
#else
  return false;
#endif
}

// Everything below the world: a collective that all ranks call in the same order.
inline void barrier() {
#ifdef NNSHADE_MPI
  if (world().size > 1) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

// Sums each value over the ranks (counts and totals for a report; the order of the
// additions is MPI's, so never use it for numbers that must be bitwise reproducible).
inline void sum_over_ranks(std::vector<double>& values) {
#ifdef NNSHADE_MPI
  if (world().size > 1)
    MPI_Allreduce(MPI_IN_PLACE, values.data(), int(values.size()), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
#endif
}

// Sends `bytes` of rank `root` to every rank (the byte count, then the bytes): each other
// rank's `bytes` is replaced by root's. For data one rank computes and all need (the NNAO
// point rows, runs/ao/train_nnao.h). A no-op for one rank and without MPI.
inline void broadcast_bytes(std::vector<char>& bytes, int root) {
#ifdef NNSHADE_MPI
  if (world().size > 1) {
    long long n = (long long)bytes.size();
    MPI_Bcast(&n, 1, MPI_LONG_LONG, root, MPI_COMM_WORLD);
    bytes.resize(size_t(n));
    // MPI counts are int: a message of more than 2 GiB goes in pieces.
    constexpr long long kPiece = 1ll << 30;
    for (long long at = 0; at < n; at += kPiece)
      MPI_Bcast(bytes.data() + at, int(std::min(kPiece, n - at)), MPI_CHAR, root, MPI_COMM_WORLD);
  }
#else
  (void)bytes;
  (void)root;
#endif
}

// Runs f on rank 0, then on the other ranks: for a shared cache (the default dataset)
// that rank 0 fills and the others then find in place.
template <class F>
auto rank0_first(F&& f) {
  if (writer()) {
    auto r = f();
    barrier();
    return r;
  }
  barrier();
  return f();
}

class Session {
 public:
  Session(int& argc, char**& argv) {
    const int launched = launcher_size();
#ifdef NNSHADE_MPI
    if (launched > 0) {
      int provided = 0;
      // Only the main thread calls MPI; the thread pool's workers never do.
      MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
      // A failed call ends the job at once (the default, said explicitly: a rank that
      // returned an error code and carried on would leave the others waiting).
      MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_ARE_FATAL);
      MPI_Comm_rank(MPI_COMM_WORLD, &world().rank);
      MPI_Comm_size(MPI_COMM_WORLD, &world().size);
      world().mpi = true;
    }
#else
    if (launched > 1) {
      // N copies that each think they are alone would all write the same folder.
      std::fprintf(stderr,
                   "%s: started by an MPI launcher with %d processes, but was built without MPI "
                   "(install libopenmpi-dev and rebuild; CMake option NNSHADE_MPI)\n",
                   argv[0], launched);
      std::exit(2);
    }
#endif
  }
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // Ends MPI and returns `code`. A rank that fails takes the job down (MPI_Abort): the
  // others may be waiting for its gradients, and a clean exit of one rank would leave
  // them waiting forever.
  int finish(int code) {
#ifdef NNSHADE_MPI
    if (world().mpi) {
      if (code != 0 && world().size > 1) {
        std::fflush(nullptr);
        MPI_Abort(MPI_COMM_WORLD, code);
      }
      MPI_Finalize();
      world().mpi = false;
    }
#endif
    return code;
  }
};

}  // namespace nns::runs
