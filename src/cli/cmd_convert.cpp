// medspheres convert IN OUT: sphere files from one format to another (medspheres' sphere
// set and robot file, cuRobo, XRDF, spherized URDF, SRDF, foam, spheretree).
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "cli_common.h"
#include "medspheres/formats/sphere_document.h"
#include "medspheres/io.h"

namespace medspheres::cli {

namespace {

struct ConvertArgs {
  std::string in, out, from, to, link, urdf, set = "outer", name;
  int level = -1;
};

std::size_t sphere_count(const formats::SphereDocument& doc) {
  if (doc.set) return doc.set->size();
  std::size_t n = 0;
  for (const auto& l : doc.links) n += l.spheres.size();
  return n;
}

int run_convert(const ConvertArgs& a) {
  using formats::parse_sphere_format;
  formats::ReadOptions read;
  read.choice = a.set == "inner" ? formats::SphereChoice::kInner : formats::SphereChoice::kOuter;
  read.level = a.level;
  const std::optional<formats::SphereFormat> from =
      a.from.empty() ? std::nullopt : std::optional(parse_sphere_format(a.from, "--from"));
  const formats::SphereFormat to =
      a.to.empty() ? formats::sphere_format_of_path(a.out) : parse_sphere_format(a.to, "--to");
  check_output_path(a.out);
  const formats::SphereDocument doc = formats::read_sphere_document(a.in, from, read);
  formats::WriteOptions write;
  write.link = a.link;
  write.robot_name = a.name;
  if (!a.urdf.empty()) {
    write.urdf_text = read_text_file(a.urdf);
    write.urdf_source = a.urdf;
  }
  formats::write_sphere_document(a.out, doc, to, write);
  std::cout << "converted " << a.in << " ("
            << (doc.set ? std::string("one set") : count_text(doc.links.size(), "link")) << ", "
            << count_text(sphere_count(doc), "sphere") << ") -> " << a.out << " ("
            << formats::sphere_format_name(to) << ")\n";
  return kExitOk;
}

}  // namespace

Runner register_convert(CLI::App& app) {
  auto a = std::make_shared<ConvertArgs>();
  CLI::App* sub = app.add_subcommand(
      "convert", "Convert sphere files: spheres, robot, curobo, xrdf, urdf, srdf, foam, sph");
  sub->add_option("in", a->in, "Input sphere file")->required()->check(non_empty);
  sub->add_option("out", a->out, "Output file (written atomically)")->required()->check(non_empty);
  sub->add_option("--from", a->from, "Input format (default: from the extension and content)");
  sub->add_option("--to", a->to, "Output format (default: from the extension)");
  sub->add_option("--link", a->link,
                  "The link a one-set output takes from a robot file, or the link a one-set "
                  "input becomes in a robot format");
  sub->add_option("--urdf", a->urdf, "The robot's URDF, for a spherized URDF output");
  sub->add_option("--set", a->set, "The set a medspheres robot file gives: outer or inner")
      ->check(CLI::IsMember({"outer", "inner"}));
  sub->add_option("--level", a->level,
                  "The level of a .sph or foam input, 0 = root (default: last)")
      ->check(CLI::Range(0, 1000));
  sub->add_option("--name", a->name, "The robot name an SRDF output carries");
  return [a] { return run_convert(*a); };
}

}  // namespace medspheres::cli
