// SphereSet, SphereDocument and the formats: load, save, convert.
#include <optional>
#include <string>

#include <pybind11/stl.h>

#include "medspheres/error.h"
#include "medspheres/formats/sphere_document.h"
#include "medspheres/io.h"
#include "medspheres/number_text.h"
#include "py_common.h"

namespace medspheres::python {

namespace {

static_assert(sizeof(Sphere) == 4 * sizeof(double), "a Sphere is x, y, z, r");

// The set's balls as an n x 4 read-only view of its memory, kept alive by \p self.
py::array spheres_view(py::object self) {
  const SphereSet& set = self.cast<const SphereSet&>();
  const auto n = static_cast<py::ssize_t>(set.size());
  const double* data = set.empty() ? nullptr : set.spheres.front().center.data();
  py::array_t<double> view({n, py::ssize_t{4}}, {py::ssize_t{sizeof(Sphere)}, py::ssize_t{8}}, data,
                           self);
  py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return std::move(view);
}

std::optional<formats::SphereFormat> format_of(const std::optional<std::string>& name) {
  if (!name) return std::nullopt;
  return formats::parse_sphere_format(*name, "format");
}

formats::SphereChoice choice_of(const std::string& set) {
  if (set == "outer") return formats::SphereChoice::kOuter;
  if (set == "inner") return formats::SphereChoice::kInner;
  throw InputError::option(ErrorKind::kOutOfRange, "set", set,
                           "must be outer or inner, got '" + set + "'");
}

formats::WriteOptions write_options(const std::string& link, const std::optional<std::string>& urdf,
                                    const std::string& name) {
  formats::WriteOptions w;
  w.link = link;
  w.robot_name = name;
  if (urdf) {
    w.urdf_text = read_text_file(*urdf);
    w.urdf_source = *urdf;
  }
  return w;
}

void save_document(const formats::SphereDocument& doc, const std::string& path,
                   const std::optional<std::string>& format, const std::string& link,
                   const std::optional<std::string>& urdf, const std::string& name) {
  const formats::SphereFormat to = format ? formats::parse_sphere_format(*format, "format")
                                          : formats::sphere_format_of_path(path);
  check_output_path(path);
  const formats::WriteOptions w = write_options(link, urdf, name);
  py::gil_scoped_release release;
  formats::write_sphere_document(path, doc, to, w);
}

formats::SphereDocument read_document(const std::string& path,
                                      const std::optional<std::string>& format,
                                      const std::string& set, int level) {
  formats::ReadOptions read;
  read.choice = choice_of(set);
  read.level = level;
  const std::optional<formats::SphereFormat> from = format_of(format);
  py::gil_scoped_release release;
  return formats::read_sphere_document(path, from, read);
}

const char* kSaveDoc =
    "Writes the spheres to `path` in `format` (default: from the extension; 'spheres', "
    "'robot', 'curobo', 'xrdf', 'urdf', 'srdf', 'foam', 'sph'), atomically, as "
    "`medspheres convert` does. `link` names the link of a per-link format (or the link a "
    "one-set output takes), `urdf` is the robot's URDF path for a spherized URDF, `name` "
    "the SRDF's robot name.";

void register_sphere_set_class(py::module_& m) {
  py::class_<SphereSet>(m, "SphereSet",
                        "A set of balls in the mesh's frame and units, with the provenance and "
                        "statistics of the file or bake it came from.")
      .def(py::init([](const py::handle& spheres, const py::object& metadata) {
             SphereSet set = sphere_set_of_array(spheres, "spheres");
             if (!metadata.is_none())
               set.metadata_json =
                   py::module_::import("json").attr("dumps")(metadata).cast<std::string>();
             validate_sphere_set(set, "spheres");
             return set;
           }),
           py::arg("spheres"), py::arg("metadata") = py::none(),
           "From an n x 4 array (x, y, z, r), copied and validated (radius > 0, finite); "
           "`metadata` a JSON-able dict kept beside the balls.")
      .def_property_readonly("spheres", &spheres_view,
                             "The balls as an n x 4 float64 array (x, y, z, r): a read-only "
                             "view of the set's memory, no copy.")
      .def_property_readonly(
          "metadata", [](const SphereSet& s) { return json_loads(s.metadata_json); },
          "Every key of the sphere-set file besides the spheres (source, generator, stats), "
          "as a dict.")
      .def_property_readonly(
          "stats",
          [](const SphereSet& s) {
            py::dict meta = json_loads(s.metadata_json);
            return meta.contains("stats") ? py::object(meta["stats"]) : py::object(py::dict());
          },
          "The 'stats' entry of the metadata (count, nerr, nerr_kind, timings, ...), as a dict.")
      .def("__len__", &SphereSet::size)
      .def("__repr__",
           [](const SphereSet& s) {
             return "<medspheres.SphereSet of " + count_text(s.size(), "sphere") + ">";
           })
      .def("to_json", &sphere_set_to_json,
           "The sphere-set file's JSON text (numbers that read back bit-identical).")
      .def(
          "save",
          [](const SphereSet& s, const py::object& path, const std::optional<std::string>& format,
             const std::string& link, const std::optional<std::string>& urdf,
             const std::string& name) {
            formats::SphereDocument doc;
            doc.set = s;
            save_document(doc, path_of(path), format, link, urdf, name);
          },
          py::arg("path"), py::arg("format") = py::none(), py::arg("link") = "",
          py::arg("urdf") = py::none(), py::arg("name") = "", kSaveDoc);
}

void register_document_class(py::module_& m) {
  py::class_<formats::SphereDocument>(
      m, "SphereDocument",
      "What a sphere file held: one set (`set`), or spheres per link (`links`); a robot "
      "file also keeps its kinematic tree.")
      .def_property_readonly(
          "set",
          [](const formats::SphereDocument& d) -> py::object {
            return d.set ? py::cast(*d.set) : py::none();
          },
          "The one set of a one-set file, or None.")
      .def_property_readonly(
          "links",
          [](const formats::SphereDocument& d) {
            py::dict out;
            for (const formats::LinkSphereList& l : d.links)
              out[py::str(l.link)] = spheres_array(l.spheres);
            return out;
          },
          "Link name -> n x 4 float64 array (x, y, z, r) in the link's frame, in file order "
          "(empty for a one-set file).")
      .def_property_readonly("robot_name",
                             [](const formats::SphereDocument& d) { return d.robot_name; })
      .def_property_readonly("is_robot_file",
                             [](const formats::SphereDocument& d) { return d.model.has_value(); })
      .def(
          "save",
          [](const formats::SphereDocument& d, const py::object& path,
             const std::optional<std::string>& format, const std::string& link,
             const std::optional<std::string>& urdf, const std::string& name) {
            save_document(d, path_of(path), format, link, urdf, name);
          },
          py::arg("path"), py::arg("format") = py::none(), py::arg("link") = "",
          py::arg("urdf") = py::none(), py::arg("name") = "", kSaveDoc);
}

}  // namespace

void register_sphere_set(py::module_& m) {
  register_sphere_set_class(m);
  register_document_class(m);
  m.def(
      "load",
      [](const py::object& path, const std::optional<std::string>& format, const std::string& set,
         int level) { return read_document(path_of(path), format, set, level); },
      py::arg("path"), py::arg("format") = py::none(), py::arg("set") = "outer",
      py::arg("level") = -1,
      "Reads any sphere file `medspheres convert` reads (format from the extension and "
      "content unless given). `set`: the set a robot file gives ('outer' or 'inner'); "
      "`level`: the level of a .sph or foam file (-1: the last). Returns a SphereDocument.");
  m.def(
      "load_spheres",
      [](const py::object& path) {
        const std::string p = path_of(path);
        py::gil_scoped_release release;
        return load_sphere_set(p);
      },
      py::arg("path"), "Reads a medspheres sphere-set file (.json) into a SphereSet.");
  m.def(
      "convert",
      [](const py::object& src, const py::object& dst, const std::optional<std::string>& from,
         const std::optional<std::string>& to, const std::string& link,
         const std::optional<std::string>& urdf, const std::string& set, int level,
         const std::string& name) {
        const formats::SphereDocument doc = read_document(path_of(src), from, set, level);
        save_document(doc, path_of(dst), to, link, urdf, name);
      },
      py::arg("src"), py::arg("dst"), py::arg("from_format") = py::none(),
      py::arg("to_format") = py::none(), py::arg("link") = "", py::arg("urdf") = py::none(),
      py::arg("set") = "outer", py::arg("level") = -1, py::arg("name") = "",
      "`medspheres convert SRC DST`: load(src, ...) then save(dst, ...).");
}

}  // namespace medspheres::python
