// thread_count (threads.h): here, in medspheres::mesh (and so available to
// the targets above it), because this component brings OpenMP; threads.h stays free of
// <omp.h>, and check_threads is header-only.
//
// kMaxThreads: the cap keeps a typo such as 100000 from asking the OpenMP runtime for more
// threads than the system can create (which crashes it); 1024 is far above the cores of
// any machine this runs on.
#include "medspheres/mesh/threads.h"

#include <algorithm>

#include <omp.h>

namespace medspheres {

int thread_count(int threads) {
  check_threads(threads);
  return threads == 0 ? std::min(omp_get_max_threads(), kMaxThreads) : threads;
}

}  // namespace medspheres
