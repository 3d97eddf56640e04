#include "medspheres/formats/srdf_spheres.h"

#include "medspheres/error.h"
#include "medspheres/io.h"
#include "number_text.h"
#include "xml_text.h"

namespace medspheres::formats {

namespace {

void add_sphere(tinyxml2::XMLElement& parent, const Eigen::Vector3d& center, double radius) {
  tinyxml2::XMLElement* s = parent.InsertNewChildElement("sphere");
  s->SetAttribute("center", exact_numbers({center.x(), center.y(), center.z()}).c_str());
  s->SetAttribute("radius", exact_number_text(radius).c_str());
}

}  // namespace

std::string srdf_spheres_text(const RobotSpheres& spheres, const std::string& robot_name,
                              const std::vector<DisabledCollision>& disabled) {
  validate_robot_spheres(spheres, "SRDF");
  tinyxml2::XMLDocument doc;
  doc.InsertEndChild(doc.NewDeclaration());
  tinyxml2::XMLElement* robot = doc.NewElement("robot");
  doc.InsertEndChild(robot);
  robot->SetAttribute("name", robot_name.c_str());
  for (const LinkSphereList& l : spheres) {
    tinyxml2::XMLElement* a = robot->InsertNewChildElement("link_sphere_approximation");
    a->SetAttribute("link", l.link.c_str());
    if (l.spheres.empty()) add_sphere(*a, Eigen::Vector3d::Zero(), 0.0);  // srdfdom: none
    for (const Sphere& s : l.spheres) add_sphere(*a, s.center, s.radius);
  }
  add_srdf_disabled_collisions(*robot, disabled);
  return xml_to_text(doc);
}

RobotSpheres parse_srdf_spheres(const std::string& text, const std::string& source) {
  tinyxml2::XMLDocument doc;
  parse_xml(doc, text, source);
  const tinyxml2::XMLElement& robot = xml_root(doc, "robot", source);
  RobotSpheres out;
  for (const tinyxml2::XMLElement* a = robot.FirstChildElement("link_sphere_approximation"); a;
       a = a->NextSiblingElement("link_sphere_approximation")) {
    LinkSphereList link;
    link.link = a->Attribute("link") ? a->Attribute("link") : "";
    for (const tinyxml2::XMLElement* s = a->FirstChildElement("sphere"); s;
         s = s->NextSiblingElement("sphere")) {
      const std::string where =
          "link \"" + link.link + "\" sphere " + std::to_string(link.spheres.size());
      const auto c = xml_numbers(*s, "center", 3, {}, source, where);
      const double r = xml_numbers(*s, "radius", 1, {}, source, where)[0];
      link.spheres.push_back({{c[0], c[1], c[2]}, r});
    }
    if (link.spheres.size() == 1 && link.spheres[0].radius == 0.0) link.spheres.clear();
    out.push_back(std::move(link));
  }
  validate_robot_spheres(out, source);
  return out;
}

RobotSpheres load_srdf_spheres(const std::string& path) {
  return parse_srdf_spheres(read_text_file(path), path);
}

}  // namespace medspheres::formats
