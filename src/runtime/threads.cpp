// thread_count (threads.h): here, in medspheres::runtime, the lowest layer, so that every
// target above it (the mesh queries, the bakes, the robot checkers) sizes its thread teams
// the same way; threads.h stays free of <omp.h>, and check_threads is header-only.
//
// kMaxThreads: the cap keeps a typo such as 100000 from asking the OpenMP runtime for more
// threads than the system can create (which crashes it); 1024 is far above the cores of
// any machine this runs on.
#include "medspheres/threads.h"

#include <algorithm>
#include <string>
#include <utility>

#include <omp.h>

#include "medspheres/error.h"
#include "medspheres/thread_option.h"

namespace medspheres {

void check_threads_option(int threads, const char* field) {
  if (std::string problem = threads_problem(threads); !problem.empty())
    throw InputError::option(ErrorKind::kOutOfRange, field, std::to_string(threads),
                             std::move(problem));
}

int thread_count(int threads) {
  check_threads(threads);
  return threads == 0 ? std::min(omp_get_max_threads(), kMaxThreads) : threads;
}

}  // namespace medspheres
