// Reading a URDF: urdfdom builds the model; tinyxml2 gives the order of the <link> and
// <joint> elements in the file (urdfdom keeps them in maps sorted by name), the parent and
// child names that the tree checks below need to name the links of a cycle, and the
// <capsule> elements (URDF's newer primitive, which urdfdom 3 does not know).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include <console_bridge/console.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include "medspheres/error.h"
#include "medspheres/io.h"
#include "medspheres/robot/urdf_robot.h"

namespace medspheres {

namespace {

// urdfdom reports problems through console_bridge and carries on in some cases (an
// unknown geometry drops its <collision> element and the model is still returned), so
// every error it logs while parsing is collected here and makes the read fail.
class UrdfdomMessages : public console_bridge::OutputHandler {
 public:
  UrdfdomMessages() : lock_(mutex()) { console_bridge::useOutputHandler(this); }
  ~UrdfdomMessages() override { console_bridge::restorePreviousOutputHandler(); }
  UrdfdomMessages(const UrdfdomMessages&) = delete;
  UrdfdomMessages& operator=(const UrdfdomMessages&) = delete;

  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level < console_bridge::CONSOLE_BRIDGE_LOG_ERROR) return;
    if (!errors_.empty()) errors_ += "; ";
    errors_ += text;
  }
  const std::string& errors() const { return errors_; }

 private:
  static std::mutex& mutex() {
    static std::mutex m;  // console_bridge's handler is process-wide
    return m;
  }
  std::lock_guard<std::mutex> lock_;
  std::string errors_;
};

struct XmlJoint {
  std::string name, parent, child;
};

// A <capsule> by where it stands: the link, visual (true) or collision (false), and its
// element's position among the link's elements of that kind.
using CapsuleKey = std::tuple<std::string, bool, std::size_t>;

struct XmlOrder {
  std::vector<std::string> links;
  std::vector<XmlJoint> joints;
  std::map<CapsuleKey, Eigen::Vector2d> capsules;  // radius, length
  std::string urdfdom_xml;  // the text urdfdom reads: capsules replaced by sphere placeholders
};

std::string attribute(const tinyxml2::XMLElement* e, const char* name) {
  const char* value = e->Attribute(name);
  return value == nullptr ? std::string() : std::string(value);
}

std::string child_link(const tinyxml2::XMLElement* joint, const char* which) {
  const tinyxml2::XMLElement* e = joint->FirstChildElement(which);
  return e == nullptr ? std::string() : attribute(e, "link");
}

// Each <capsule radius length> under the link's <visual> or <collision> elements is
// recorded and replaced by a <sphere> of its radius, which urdfdom reads; to_part turns
// the placeholder back into the capsule.
void take_capsules(tinyxml2::XMLElement* link, bool visual, const std::string& source,
                   XmlOrder& order) {
  const char* kind = visual ? "visual" : "collision";
  std::size_t index = 0;
  for (auto* e = link->FirstChildElement(kind); e; e = e->NextSiblingElement(kind), ++index) {
    tinyxml2::XMLElement* geometry = e->FirstChildElement("geometry");
    tinyxml2::XMLElement* capsule = geometry ? geometry->FirstChildElement("capsule") : nullptr;
    if (capsule == nullptr) continue;
    const std::string name = attribute(link, "name");
    double radius = 0, length = 0;
    if (capsule->QueryDoubleAttribute("radius", &radius) != tinyxml2::XML_SUCCESS ||
        capsule->QueryDoubleAttribute("length", &length) != tinyxml2::XML_SUCCESS ||
        !(radius > 0.0 && std::isfinite(radius)) || !(length >= 0.0 && std::isfinite(length)))
      throw InputError(source, "link '" + name + "': a <capsule> needs a radius > 0 and a " +
                                   "length >= 0 (finite numbers)");
    order.capsules[{name, visual, index}] = Eigen::Vector2d(radius, length);
    tinyxml2::XMLElement* sphere = geometry->InsertNewChildElement("sphere");
    sphere->SetAttribute("radius", radius);
    geometry->DeleteChild(capsule);
  }
}

XmlOrder scan_xml(const std::string& xml, const std::string& source) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS)
    throw InputError(source, std::string("not well-formed XML: ") + doc.ErrorStr());
  tinyxml2::XMLElement* robot = doc.FirstChildElement("robot");
  if (robot == nullptr) throw InputError(source, "no <robot> element");
  XmlOrder order;
  for (auto* e = robot->FirstChildElement("link"); e; e = e->NextSiblingElement("link")) {
    order.links.push_back(attribute(e, "name"));
    take_capsules(e, false, source, order);
    take_capsules(e, true, source, order);
  }
  for (auto* e = robot->FirstChildElement("joint"); e; e = e->NextSiblingElement("joint"))
    order.joints.push_back({attribute(e, "name"), child_link(e, "parent"), child_link(e, "child")});
  if (order.capsules.empty()) {
    order.urdfdom_xml = xml;
  } else {
    tinyxml2::XMLPrinter printer;
    doc.Print(&printer);
    order.urdfdom_xml = printer.CStr();
  }
  return order;
}

// One parent per link and no cycle, with the links named (urdfdom keeps the last parent
// of a link that has two, and says only "no root link" for a cycle).
void check_tree(const XmlOrder& order, const std::string& source) {
  std::map<std::string, const XmlJoint*> parent_joint;
  for (const std::string& link : order.links)
    if (link.empty()) throw InputError(source, "a <link> has an empty name");
  for (const XmlJoint& j : order.joints) {
    auto [it, fresh] = parent_joint.emplace(j.child, &j);
    if (!fresh)
      throw InputError(source, "link '" + j.child + "' is the child of two joints ('" +
                                   it->second->name + "' and '" + j.name + "')");
  }
  for (const std::string& start : order.links) {
    std::vector<std::string> path{start};
    std::set<std::string> seen{start};
    for (auto it = parent_joint.find(start); it != parent_joint.end();
         it = parent_joint.find(it->second->parent)) {
      const std::string& parent = it->second->parent;
      if (!seen.insert(parent).second) {
        std::string cycle;
        for (const std::string& l : path) cycle += "'" + l + "' -> ";
        throw InputError(source, "joint cycle through links " + cycle + "'" + parent + "'");
      }
      path.push_back(parent);
    }
  }
}

Eigen::Isometry3d to_isometry(const urdf::Pose& p) {
  Eigen::Quaterniond q(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z);
  q.normalize();
  Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
  x.linear() = q.toRotationMatrix();
  x.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return x;
}

Eigen::Vector3d to_vector(const urdf::Vector3& v) {
  return {v.x, v.y, v.z};
}

Joint to_joint(const urdf::Joint& j, const std::string& source) {
  Joint out;
  out.name = j.name;
  out.parent = j.parent_link_name;
  out.child = j.child_link_name;
  out.origin = to_isometry(j.parent_to_joint_origin_transform);
  switch (j.type) {
    case urdf::Joint::FIXED:
      out.type = JointType::kFixed;
      break;
    case urdf::Joint::REVOLUTE:
      out.type = JointType::kRevolute;
      break;
    case urdf::Joint::CONTINUOUS:
      out.type = JointType::kContinuous;
      break;
    case urdf::Joint::PRISMATIC:
      out.type = JointType::kPrismatic;
      break;
    default:
      throw InputError(source, "joint '" + j.name +
                                   "': unsupported joint type (fixed, revolute, continuous and "
                                   "prismatic are supported; floating and planar only from a "
                                   "root link without geometry)");
  }
  const Eigen::Vector3d axis = to_vector(j.axis);
  if (out.type != JointType::kFixed) {
    if (!(axis.norm() > 0.0) || !axis.allFinite())
      throw InputError(source, "joint '" + j.name + "': axis must be a non-zero vector");
    out.axis = axis.normalized();
  }
  if (j.limits)
    out.limits =
        JointLimits{j.limits->lower, j.limits->upper, j.limits->velocity, j.limits->effort};
  // A fixed joint never moves, so its <mimic> (VAMP's Panda has one on a finger) means
  // nothing, like its <axis>: it is dropped, not refused.
  if (j.mimic && out.type != JointType::kFixed)
    out.mimic = JointMimic{j.mimic->joint_name, j.mimic->multiplier, j.mimic->offset};
  return out;
}

bool positive(double v) {
  return v > 0.0 && std::isfinite(v);
}

// \p capsule: (radius, length) when the element was a <capsule> (its geometry here is the
// sphere placeholder scan_xml put in its place), else nullptr.
LinkPart to_part(const urdf::Geometry& g, const urdf::Pose& origin, const Eigen::Vector2d* capsule,
                 const std::string& base_dir, const UrdfReadOptions& options) {
  LinkPart part;
  part.origin = to_isometry(origin);
  if (capsule != nullptr) {
    part.shape = PartShape::kCapsule;
    part.size = Eigen::Vector3d(capsule->x(), capsule->x(), capsule->y());
    return part;  // sizes checked by scan_xml
  }
  if (const auto* s = dynamic_cast<const urdf::Sphere*>(&g)) {
    part.shape = PartShape::kSphere;
    part.size = Eigen::Vector3d::Constant(s->radius);
  } else if (const auto* b = dynamic_cast<const urdf::Box*>(&g)) {
    part.shape = PartShape::kBox;
    part.size = to_vector(b->dim);
  } else if (const auto* c = dynamic_cast<const urdf::Cylinder*>(&g)) {
    part.shape = PartShape::kCylinder;
    part.size = Eigen::Vector3d(c->radius, c->radius, c->length);
  } else if (const auto* m = dynamic_cast<const urdf::Mesh*>(&g)) {
    part.shape = PartShape::kMesh;
    part.uri = m->filename;
    part.scale = to_vector(m->scale);
    if (!part.scale.allFinite() || part.scale.prod() == 0.0)
      throw InputError("mesh scale",
                       "must be finite and non-zero, got " + std::to_string(part.scale.x()) + " " +
                           std::to_string(part.scale.y()) + " " + std::to_string(part.scale.z()));
    part.path = resolve_mesh_path(part.uri, base_dir, options.packages);
    return part;
  } else {
    throw InputError("geometry", "unsupported geometry type");
  }
  if (!positive(part.size.x()) || !positive(part.size.y()) || !positive(part.size.z()))
    throw InputError("geometry", "empty primitive: every size must be finite and > 0");
  return part;
}

// A primitive of size zero in every dimension: a placeholder that holds nothing (Kinova's
// descriptions give their root link a box of size "0 0 0"), read as no geometry.
bool placeholder(const urdf::Geometry& g) {
  if (const auto* s = dynamic_cast<const urdf::Sphere*>(&g)) return s->radius == 0.0;
  if (const auto* b = dynamic_cast<const urdf::Box*>(&g))
    return b->dim.x == 0.0 && b->dim.y == 0.0 && b->dim.z == 0.0;
  if (const auto* c = dynamic_cast<const urdf::Cylinder*>(&g))
    return c->radius == 0.0 && c->length == 0.0;
  return false;
}

// urdfdom keeps a link's elements of each kind in the file's order, so the i-th one is
// the i-th <visual> or <collision> element that scan_xml counted.
template <typename Element>
void add_parts(const std::vector<std::shared_ptr<Element>>& elements, const std::string& link,
               bool visual, const XmlOrder& order, const std::string& base_dir,
               const UrdfReadOptions& options, std::vector<LinkPart>& parts) {
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const auto& e = elements[i];
    if (!e || !e->geometry || placeholder(*e->geometry)) continue;
    const auto capsule = order.capsules.find({link, visual, i});
    parts.push_back(to_part(*e->geometry, e->origin,
                            capsule == order.capsules.end() ? nullptr : &capsule->second, base_dir,
                            options));
  }
}

UrdfLink to_link(const urdf::Link& link, const XmlOrder& order, const std::string& source,
                 const std::string& base_dir, const UrdfReadOptions& options) {
  UrdfLink out;
  out.name = link.name;
  try {
    auto collisions = link.collision_array;
    if (collisions.empty() && link.collision) collisions.push_back(link.collision);
    add_parts(collisions, link.name, false, order, base_dir, options, out.parts);
    if (out.parts.empty() && options.from_visual) {
      auto visuals = link.visual_array;
      if (visuals.empty() && link.visual) visuals.push_back(link.visual);
      add_parts(visuals, link.name, true, order, base_dir, options, out.parts);
      out.from_visual = !out.parts.empty();
    }
  } catch (const InputError& e) {
    throw InputError(source, "link '" + link.name + "': " + e.what());
  }
  return out;
}

const char* free_type(const urdf::Joint& j) {
  if (j.type == urdf::Joint::FLOATING) return "floating";
  if (j.type == urdf::Joint::PLANAR) return "planar";
  return nullptr;
}

// A floating or planar joint \p j moves the whole robot below it, and planners take a fixed
// base. It is taken only from the root link, when that link carries no geometry and has no
// other joint (the "world" link that simulators add): the two are left out of \p robot, and
// the robot is the tree of the joint's child.
void leave_out_free_base(const urdf::Joint& j, const XmlOrder& order, UrdfRobot& robot,
                         const std::string& source) {
  const std::string type = free_type(j), root = robot.model.root_link;
  const std::string what = "joint '" + j.name + "': a " + type +
                           " joint is taken only from a root link without geometry or other "
                           "joints (the robot's base is then its child), and ";
  if (j.parent_link_name != root)
    throw InputError(
        source, what + "its parent '" + j.parent_link_name + "' is not the root '" + root + "'");
  for (const XmlJoint& other : order.joints)
    if (other.parent == root && other.name != j.name)
      throw InputError(source,
                       what + "the root '" + root + "' has the joint '" + other.name + "' too");
  const auto link = std::find_if(robot.links.begin(), robot.links.end(),
                                 [&](const UrdfLink& l) { return l.name == root; });
  if (!link->parts.empty())
    throw InputError(source, what + "the root '" + root + "' carries geometry");
  robot.model.links.erase(robot.model.links.begin() + (link - robot.links.begin()));
  robot.links.erase(link);
  robot.model.root_link = j.child_link_name;
  robot.free_base = {j.name, type, root};
}

}  // namespace

UrdfRobot parse_urdf(const std::string& xml, const std::string& source, const std::string& base_dir,
                     const UrdfReadOptions& options) {
  const XmlOrder order = scan_xml(xml, source);
  check_tree(order, source);
  urdf::ModelInterfaceSharedPtr model;
  {
    UrdfdomMessages messages;
    model = urdf::parseURDF(order.urdfdom_xml);
    if (!messages.errors().empty()) throw InputError(source, "urdfdom: " + messages.errors());
  }
  if (!model) throw InputError(source, "urdfdom could not read the robot");
  UrdfRobot robot;
  robot.path = source;
  robot.model.name = model->getName();
  robot.model.root_link = model->getRoot() ? model->getRoot()->name : std::string();
  for (const std::string& name : order.links) {
    const urdf::LinkConstSharedPtr link = model->getLink(name);
    if (!link) throw InputError(source, "link '" + name + "' was not read by urdfdom");
    robot.links.push_back(to_link(*link, order, source, base_dir, options));
    Link entry;
    entry.name = name;
    robot.model.links.push_back(std::move(entry));
  }
  for (const XmlJoint& j : order.joints) {
    const urdf::JointConstSharedPtr joint = model->getJoint(j.name);
    if (!joint) throw InputError(source, "joint '" + j.name + "' was not read by urdfdom");
    if (free_type(*joint))
      leave_out_free_base(*joint, order, robot, source);
    else
      robot.model.joints.push_back(to_joint(*joint, source));
  }
  validate_robot_model(robot.model, source);  // limits, mimic chains
  return robot;
}

std::vector<std::string> robot_input_files(const UrdfRobot& robot) {
  std::vector<std::string> files{robot.path};
  for (const UrdfLink& link : robot.links)
    for (const LinkPart& part : link.parts)
      if (part.shape == PartShape::kMesh &&
          std::find(files.begin(), files.end(), part.path) == files.end())
        files.push_back(part.path);
  return files;
}

UrdfRobot read_urdf(const std::string& path, const UrdfReadOptions& options) {
  const std::string dir = std::filesystem::path(path).parent_path().string();
  return parse_urdf(read_text_file(path), path, dir, options);
}

void require_same_links(const RobotModel& sets, const UrdfRobot& robot, const std::string& file) {
  for (const Link& l : robot.model.links)
    if (sets.find_link(l.name) == nullptr)
      throw InputError(file, "link \"" + l.name + "\" of " + robot.path + " is missing");
  if (sets.links.size() != robot.model.links.size())
    throw InputError(file, "its links are not those of " + robot.path);
}

}  // namespace medspheres
