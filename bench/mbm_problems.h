#pragma once
// MotionBenchMaker's problems as VAMP's resources ship them (resources/ROBOT/problems.tar.bz2:
// one folder per problem set, each problem a MoveIt planning scene sceneNNNN.yaml and a
// request requestNNNN.yaml), read with yaml-cpp: each scene's primitives and the request's
// start and goal. Cylinders become capsules of the same axis, radius and length, as VAMP's
// problem_dict_to_vamp makes them, and boxes of half extents (r, r, length / 2) in the "box"
// set, as it does there.

#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace medspheres::bench {

struct Primitive {
  enum class Kind { sphere, box, capsule } kind = Kind::sphere;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // in W; a capsule's axis is z
  Eigen::Vector3d half = Eigen::Vector3d::Zero();          // box: half extents
  double radius = 0.0, length = 0.0;                       // sphere, capsule (its segment)
};

struct PrimitiveScene {
  std::string name;
  std::vector<Primitive> items;
};

struct MbmProblem {
  std::string set, file;  // the set's folder name, the scene file
  PrimitiveScene scene;
  std::vector<double> start, goal;  // in the order of the joints asked for
};

/// The first \p per_set problems (in number order) of every set folder of \p dir (in name
/// order), their start and goal over \p joints. Throws std::runtime_error naming the file for
/// a problem that cannot be read, lacks a joint or holds a primitive of another type.
std::vector<MbmProblem> load_mbm_problems(const std::string& dir, std::size_t per_set,
                                          const std::vector<std::string>& joints);

}  // namespace medspheres::bench
