// Eigen runs a large enough GEMM on all of omp_get_max_threads() threads. For the
// soft module's products (tens of columns: J^T H J, dx/dz, the sensitivities' n
// right-hand sides) the fork/join and its per-call buffers cost more than the
// product, and on a shared machine far more (measured, 2 threads: a forward-sensitivity
// Jacobian 4-10x and a rotation-strain rollout 5.6x the 1-thread wall time). While
// alive, this sets the calling thread's OpenMP thread count (an ICV: other threads
// are not affected) to 1; explicit loops that want threads ask for `threads`.
#pragma once
#include <omp.h>

namespace pliant::soft {

class SerialEigenProducts {
 public:
  SerialEigenProducts() : threads(omp_get_max_threads()) { omp_set_num_threads(1); }
  ~SerialEigenProducts() { omp_set_num_threads(threads); }
  SerialEigenProducts(const SerialEigenProducts&) = delete;
  SerialEigenProducts& operator=(const SerialEigenProducts&) = delete;
  const int threads;  // the caller's count, restored on exit
};

}  // namespace pliant::soft
