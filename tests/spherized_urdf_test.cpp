#include <urdf_parser/urdf_parser.h>
#include <catch2/catch.hpp>

#include "medspheres/formats/spherized_urdf.h"
#include "support/robot_spheres_fixtures.h"

using Catch::Matchers::Contains;
using namespace medspheres::formats;
using medspheres::test::awkward_urdf;
using medspheres::test::kAwkwardLink;
using medspheres::test::random_robot_spheres;

TEST_CASE("the spherized URDF parses with urdfdom, one collision element per sphere",
          "[formats][urdf]") {
  const RobotSpheres s = random_robot_spheres(21);
  const std::string text = spherize_urdf(awkward_urdf(), s, "arm.urdf");
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(text);
  REQUIRE(model);
  CHECK(model->getName() == "awk&ward");
  for (const LinkSphereList& l : s) {
    const urdf::LinkConstSharedPtr link = model->getLink(l.link);  // escaped names survive
    REQUIRE(link);
    REQUIRE(link->collision_array.size() == l.spheres.size());
    for (std::size_t i = 0; i < l.spheres.size(); ++i) {
      const urdf::CollisionSharedPtr& c = link->collision_array[i];
      REQUIRE(c->geometry->type == urdf::Geometry::SPHERE);
      // urdfdom reads numbers with its own parser: equal to the written double.
      CHECK(std::static_pointer_cast<urdf::Sphere>(c->geometry)->radius == l.spheres[i].radius);
      CHECK(c->origin.position.x == l.spheres[i].center.x());
      CHECK(c->origin.position.y == l.spheres[i].center.y());
      CHECK(c->origin.position.z == l.spheres[i].center.z());
    }
  }
  // Everything else is kept: visuals, inertials, the link without spheres, joints, comments.
  const urdf::LinkConstSharedPtr base = model->getLink("base");
  REQUIRE(base->visual);
  CHECK(std::static_pointer_cast<urdf::Mesh>(base->visual->geometry)->filename ==
        "package://pkg/base.stl");
  CHECK(model->getLink(kAwkwardLink)->inertial->mass == 1.5);
  REQUIRE(model->getLink("no_spheres")->collision_array.size() == 1);
  CHECK(model->getLink("no_spheres")->collision->geometry->type == urdf::Geometry::SPHERE);
  CHECK(model->getJoint("j1")->limits->upper == 1.0);
  CHECK_THAT(text, Contains("<!-- kept as it was -->"));
}
