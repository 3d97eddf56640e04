// thread_count (threads.h): here because this component brings OpenMP.
#include "medspheres/mesh/threads.h"

#include <algorithm>

#include <omp.h>

namespace medspheres {

int thread_count(int threads) {
  check_threads(threads);
  return threads == 0 ? std::min(omp_get_max_threads(), kMaxThreads) : threads;
}

}  // namespace medspheres
