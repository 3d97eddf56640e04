#include "medspheres/formats/spherized_urdf.h"

#include <map>

#include "medspheres/error.h"
#include "medspheres/io.h"
#include "number_text.h"
#include "xml_text.h"

namespace medspheres::formats {

namespace {

using tinyxml2::XMLElement;

std::string link_where(const XMLElement& link) {
  const char* name = link.Attribute("name");
  return "link \"" + std::string(name ? name : "") + "\"";
}

XMLElement* sphere_collision(tinyxml2::XMLDocument& doc, const Sphere& s) {
  XMLElement* collision = doc.NewElement("collision");
  XMLElement* origin = collision->InsertNewChildElement("origin");
  origin->SetAttribute("xyz", exact_numbers({s.center.x(), s.center.y(), s.center.z()}).c_str());
  XMLElement* sphere =
      collision->InsertNewChildElement("geometry")->InsertNewChildElement("sphere");
  sphere->SetAttribute("radius", exact_number_text(s.radius).c_str());
  return collision;
}

// Replaces the <collision> children of \p link by one per sphere.
void replace_collisions(tinyxml2::XMLDocument& doc, XMLElement& link,
                        const std::vector<Sphere>& spheres) {
  std::vector<XMLElement*> old;
  for (XMLElement* c = link.FirstChildElement("collision"); c;
       c = c->NextSiblingElement("collision"))
    old.push_back(c);
  tinyxml2::XMLNode* after = old.empty() ? link.LastChild() : old.front()->PreviousSibling();
  for (const Sphere& s : spheres) {
    XMLElement* c = sphere_collision(doc, s);
    if (after)
      link.InsertAfterChild(after, c);
    else
      link.InsertFirstChild(c);
    after = c;
  }
  for (XMLElement* c : old) link.DeleteChild(c);
}

}  // namespace

std::string spherize_urdf(const std::string& urdf_text, const RobotSpheres& spheres,
                          const std::string& source) {
  validate_robot_spheres(spheres, source);
  tinyxml2::XMLDocument doc;
  parse_xml(doc, urdf_text, source);
  XMLElement& robot = xml_root(doc, "robot", source);
  std::map<std::string, XMLElement*> links;
  for (XMLElement* l = robot.FirstChildElement("link"); l; l = l->NextSiblingElement("link"))
    if (const char* name = l->Attribute("name"))
      if (!links.emplace(name, l).second)
        throw InputError(source, "link \"" + std::string(name) + "\" is defined twice");
  for (const LinkSphereList& l : spheres) {
    const auto it = links.find(l.link);
    if (it == links.end())
      throw InputError(source, "link \"" + l.link + "\" has spheres but is not in the URDF");
    replace_collisions(doc, *it->second, l.spheres);
  }
  // tinyxml2 reads some text it does not print back as well-formed XML (stray content after
  // the root, control characters): such a URDF is refused rather than written broken.
  std::string out = xml_to_text(doc);
  tinyxml2::XMLDocument written;
  parse_xml(written, out, source + " (as written back)");
  return out;
}

RobotSpheres parse_urdf_spheres(const std::string& urdf_text, const std::string& source) {
  tinyxml2::XMLDocument doc;
  parse_xml(doc, urdf_text, source);
  const XMLElement& robot = xml_root(doc, "robot", source);
  RobotSpheres out;
  for (const XMLElement* l = robot.FirstChildElement("link"); l;
       l = l->NextSiblingElement("link")) {
    LinkSphereList link;
    link.link = l->Attribute("name") ? l->Attribute("name") : "";
    for (const XMLElement* c = l->FirstChildElement("collision"); c;
         c = c->NextSiblingElement("collision")) {
      const XMLElement* geometry = c->FirstChildElement("geometry");
      const XMLElement* sphere = geometry ? geometry->FirstChildElement("sphere") : nullptr;
      if (!sphere) continue;
      const std::string where =
          link_where(*l) + " collision sphere " + std::to_string(link.spheres.size());
      const XMLElement* origin = c->FirstChildElement("origin");
      const std::vector<double> xyz = origin
                                          ? xml_numbers(*origin, "xyz", 3, {0, 0, 0}, source, where)
                                          : std::vector<double>{0, 0, 0};
      const double r = xml_numbers(*sphere, "radius", 1, {}, source, where)[0];
      link.spheres.push_back({{xyz[0], xyz[1], xyz[2]}, r});
    }
    if (!link.spheres.empty()) out.push_back(std::move(link));
  }
  validate_robot_spheres(out, source);
  return out;
}

RobotSpheres load_urdf_spheres(const std::string& path) {
  return parse_urdf_spheres(read_text_file(path), path);
}

}  // namespace medspheres::formats
