// Thread counts (threads.h): the one resolution of a `threads` option, and its cap in the
// batch queries of MeshQuery.
#include <algorithm>
#include <stdexcept>
#include <vector>

#include <omp.h>

#include <catch2/catch.hpp>

#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/threads.h"

using namespace medspheres;

TEST_CASE("thread_count: 0 is OpenMP's team size, 1 to kMaxThreads as given", "[threads]") {
  CHECK(thread_count(0) == std::min(omp_get_max_threads(), kMaxThreads));
  CHECK(thread_count(1) == 1);
  CHECK(thread_count(7) == 7);
  CHECK(thread_count(kMaxThreads) == kMaxThreads);
  for (const int bad : {-1, kMaxThreads + 1, 100000}) {
    INFO("threads " << bad);
    CHECK_THROWS_AS(thread_count(bad), std::invalid_argument);
    CHECK_FALSE(threads_problem(bad).empty());
  }
  CHECK(threads_problem(0).empty());
  CHECK_THROWS_WITH(check_threads(-1), "threads must be in [0, 1024] (0: all cores), got -1");
}

TEST_CASE("MeshQuery's batch queries take capped thread counts", "[threads][mesh_query]") {
  // More threads than the system can create would crash the OpenMP runtime: every batch
  // query refuses a count above kMaxThreads before it starts a thread.
  const MeshQuery q(make_icosphere(1.0, 2));
  const std::vector<Eigen::Vector3d> points = {Eigen::Vector3d(0.1, 0.2, 0.3),
                                               Eigen::Vector3d(2.0, 0.0, 0.0)};
  for (const int bad : {-1, kMaxThreads + 1, 100000}) {
    INFO("threads " << bad);
    CHECK_THROWS_AS(q.closest_points(points, bad), std::invalid_argument);
    CHECK_THROWS_AS(q.winding_numbers(points, bad), std::invalid_argument);
  }
  const std::vector<ClosestPoint> one = q.closest_points(points, 1);
  const std::vector<ClosestPoint> three = q.closest_points(points, 3);
  REQUIRE(one.size() == three.size());
  for (std::size_t i = 0; i < one.size(); ++i) CHECK(one[i].point == three[i].point);
  CHECK(q.winding_numbers(points, 3) == q.winding_numbers(points, 1));
}
