#pragma once
/// \file
/// The pairs of links an SRDF excludes from self-collision checking:
/// `<disable_collisions link1="a" link2="b" reason="Adjacent"/>` (srdfdom's element).
/// Other SRDF elements are ignored. XML through tinyxml2.

#include <string>
#include <utility>
#include <vector>

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

}  // namespace medspheres::formats
