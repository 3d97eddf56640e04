// SRDF <disable_collisions> through tinyxml2.
#include "medspheres/formats/srdf_disabled_collisions.h"

#include <algorithm>

#include <tinyxml2.h>

#include "medspheres/error.h"
#include "medspheres/io.h"
#include "xml_text.h"

namespace medspheres::formats {

std::vector<DisabledCollision> parse_srdf_disabled_collisions(const std::string& text,
                                                              const std::string& source) {
  tinyxml2::XMLDocument doc;
  parse_xml(doc, text, source);
  const tinyxml2::XMLElement& robot = xml_root(doc, "robot", source);
  std::vector<DisabledCollision> out;
  for (const tinyxml2::XMLElement* e = robot.FirstChildElement("disable_collisions"); e != nullptr;
       e = e->NextSiblingElement("disable_collisions")) {
    const char* a = e->Attribute("link1");
    const char* b = e->Attribute("link2");
    if (a == nullptr || b == nullptr || *a == '\0' || *b == '\0')
      throw InputError(source, "<disable_collisions> on line " + std::to_string(e->GetLineNum()) +
                                   " needs non-empty link1 and link2");
    const char* reason = e->Attribute("reason");
    out.push_back({a, b, reason != nullptr ? reason : ""});
  }
  return out;
}

std::vector<DisabledCollision> load_srdf_disabled_collisions(const std::string& path) {
  return parse_srdf_disabled_collisions(read_text_file(path), path);
}

std::vector<std::string> parse_srdf_end_effector_links(const std::string& text,
                                                       const std::string& source) {
  tinyxml2::XMLDocument doc;
  parse_xml(doc, text, source);
  const tinyxml2::XMLElement& robot = xml_root(doc, "robot", source);
  std::vector<std::string> out;
  for (const tinyxml2::XMLElement* e = robot.FirstChildElement("end_effector"); e != nullptr;
       e = e->NextSiblingElement("end_effector")) {
    const char* link = e->Attribute("parent_link");
    if (link == nullptr || *link == '\0')
      throw InputError(source, "<end_effector> on line " + std::to_string(e->GetLineNum()) +
                                   " needs a non-empty parent_link");
    if (std::find(out.begin(), out.end(), link) == out.end()) out.push_back(link);
  }
  return out;
}

void add_srdf_disabled_collisions(tinyxml2::XMLElement& robot,
                                  const std::vector<DisabledCollision>& pairs) {
  for (const DisabledCollision& p : pairs) {
    tinyxml2::XMLElement* e = robot.InsertNewChildElement("disable_collisions");
    e->SetAttribute("link1", p.link1.c_str());
    e->SetAttribute("link2", p.link2.c_str());
    if (!p.reason.empty()) e->SetAttribute("reason", p.reason.c_str());
  }
}

}  // namespace medspheres::formats
