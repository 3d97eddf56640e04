#pragma once
/// \file
/// What a planner setup takes from an SRDF (srdfdom's elements): the pairs of links it
/// excludes from self-collision checking, `<disable_collisions link1="a" link2="b"
/// reason="Adjacent"/>`, and its end effectors, `<end_effector name="hand"
/// parent_link="link8" group="hand"/>` (the link each is attached to). Other SRDF elements
/// are ignored. XML through tinyxml2.

#include <string>
#include <utility>
#include <vector>

namespace tinyxml2 {
class XMLElement;
}

namespace medspheres::formats {

/// One excluded pair, as written (link1, link2), and the reason attribute ("" if absent).
struct DisabledCollision {
  std::string link1;
  std::string link2;
  std::string reason;
};

/// Every <disable_collisions> child of the root <robot>, in document order.
/// \throws InputError naming \p source for malformed XML, a root that is not <robot>, or an
///   element without a non-empty link1 or link2 (with its line).
std::vector<DisabledCollision> parse_srdf_disabled_collisions(const std::string& text,
                                                              const std::string& source);
std::vector<DisabledCollision> load_srdf_disabled_collisions(const std::string& path);

/// The parent_link of every <end_effector> child of the root <robot>, in document order,
/// each once.
/// \throws InputError naming \p source for malformed XML, a root that is not <robot>, or an
///   end effector without a non-empty parent_link (with its line).
std::vector<std::string> parse_srdf_end_effector_links(const std::string& text,
                                                       const std::string& source);

/// The elements written into the SRDF sidecar (srdf_spheres.h): one <disable_collisions>
/// per pair, link1, link2 and, when not empty, reason.
void add_srdf_disabled_collisions(tinyxml2::XMLElement& robot,
                                  const std::vector<DisabledCollision>& pairs);

}  // namespace medspheres::formats
