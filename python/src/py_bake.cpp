// bake, evaluate and load_mesh: the library's bake pipeline and evaluation.
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "medspheres/bake/bake_pipeline.h"
#include "medspheres/formats/sphere_document.h"
#include "medspheres/io.h"
#include "medspheres/measure/evaluate_set.h"
#include "medspheres/measure/solid_choice.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/options/bake_flags.h"
#include "py_common.h"

namespace medspheres::python {

namespace {

// The mesh argument loaded (a path) or prepared (a pair of arrays), named \p name.
LoadedMesh mesh_arg(const py::handle& mesh, std::string& name) {
  if (is_path(mesh)) {
    name = path_of(mesh);
    py::gil_scoped_release release;
    return load_mesh(name);
  }
  TriangleMesh m = mesh_of_arrays(mesh);
  if (name.empty()) name = "mesh";
  py::gil_scoped_release release;
  return prepare_mesh(std::move(m), name);
}

SphereSet bake_py(const py::handle& mesh, const std::string& method, int resolution,
                  double object_angle, double medial_tolerance,
                  std::optional<long long> max_spheres, std::optional<double> target_error,
                  bool dilate, const py::object& vertex_tolerance, const py::object& max_protrusion,
                  const py::object& cover, std::uint64_t seed, int threads,
                  const std::string& solid, int robust_resolution,
                  const py::object& robust_thickness, const py::object& cover_start,
                  double protrusion_allowance, int protrusion_restarts, int balance_rounds,
                  std::string name) {
  BakeFlags f;
  f.method = method;
  f.resolution = resolution;
  f.object_angle = object_angle;
  f.medial_tolerance = medial_tolerance;
  f.max_spheres = max_spheres;
  f.target_error = target_error;
  f.dilation = {dilate, length_text(vertex_tolerance, "vertex_tolerance"),
                length_text(max_protrusion, "max_protrusion"), length_text(cover, "cover"), seed};
  f.threads = threads;
  f.solid = {solid, robust_resolution, length_text(robust_thickness, "robust_thickness")};
  f.cover_search = {protrusion_allowance, protrusion_restarts, balance_rounds};
  if (is_path(cover_start))
    f.cover_start =
        formats::one_set_of(formats::read_sphere_document(path_of(cover_start)), "", "cover_start");
  else if (!cover_start.is_none())
    f.cover_start = sphere_set_of(cover_start, "cover_start").spheres;
  const BakeRequest request = bake_request(f);
  BakeOutcome outcome;
  std::vector<std::string> warnings;
  if (is_path(mesh)) {
    const std::string path = path_of(mesh);
    {
      py::gil_scoped_release release;
      outcome = bake_file(path, request, &warnings);
    }
    warn_all(warnings, path);
  } else {
    const LoadedMesh loaded = mesh_arg(mesh, name);
    warn_all(loaded.warnings, name);
    py::gil_scoped_release release;
    outcome = bake_mesh(loaded.mesh, loaded.report, request, name);
  }
  return std::move(outcome.spheres);
}

py::object evaluate_py(const py::handle& mesh, const py::handle& spheres, long long samples,
                       long long surface_samples, std::uint64_t seed, int threads,
                       const std::string& solid, int robust_resolution,
                       const py::object& robust_thickness) {
  const FitOptions options = fit_options(samples, surface_samples, seed, threads);
  // The solid is chosen by the library (eval_solid), from the request the options layer
  // reads, as the CLI's eval does.
  const SolidRequest asked =
      solid_request({solid, robust_resolution, length_text(robust_thickness, "robust_thickness")});
  std::string mesh_name;
  const LoadedMesh loaded = mesh_arg(mesh, mesh_name);
  std::string spheres_name = "spheres";
  SphereSet set;
  if (is_path(spheres)) {
    spheres_name = path_of(spheres);
    set = load_sphere_set(spheres_name);
  } else {
    set = sphere_set_of(spheres, "spheres");
  }
  std::string json;
  {
    py::gil_scoped_release release;
    json = evaluation_json(evaluate_mesh_set(loaded, mesh_name, set, spheres_name, options, asked));
  }
  return json_loads(json);
}

}  // namespace

void register_bake(py::module_& m) {
  const BakeOptions d;
  m.def("bake", &bake_py, py::arg("mesh"), py::kw_only(), py::arg("method") = "medial",
        py::arg("resolution") = d.resolution, py::arg("object_angle") = d.object_angle,
        py::arg("medial_tolerance") = 0.0, py::arg("max_spheres") = py::none(),
        py::arg("target_error") = py::none(), py::arg("dilate") = false,
        py::arg("vertex_tolerance") = py::none(), py::arg("max_protrusion") = py::none(),
        py::arg("cover") = py::none(), py::arg("seed") = BakeRequest{}.seed, py::arg("threads") = 0,
        py::arg("solid") = "auto", py::arg("robust_resolution") = RobustSolidOptions{}.resolution,
        py::arg("robust_thickness") = py::none(), py::arg("cover_start") = py::none(),
        py::arg("protrusion_allowance") = CoverSearch{}.protrusion_allowance,
        py::arg("protrusion_restarts") = CoverSearch{}.protrusion_restarts,
        py::arg("balance_rounds") = CoverSearch{}.balance_rounds, py::arg("name") = "",
        "Bakes spheres of a mesh, as `medspheres bake` does, and returns a SphereSet.\n\n"
        "mesh: a file path (STL, OBJ, PLY, OFF, DAE, glTF, ...) or a pair (vertices n x 3, "
        "triangles m x 3) of arrays, oriented as load_mesh orients a file.\n"
        "method: 'medial' (inner spheres S_D; S+ with dilate or cover) or 'cover' (at most "
        "max_spheres spheres whose union contains the whole surface, certified; "
        "stats['certified'] says whether the certificate holds).\n"
        "cover_start: with method 'cover', instead of max_spheres: spheres (a SphereSet, an "
        "n x 4 array, or a sphere file of one set or one link) that need not cover, made "
        "into a certified cover of at most as many, each grown or shrunk to the surface "
        "nearest it, then tightened (generator params mode 'cover_tighten').\n"
        "protrusion_allowance, protrusion_restarts, balance_rounds: with method 'cover' and "
        "max_spheres, the search's trade and effort (CoverSearch; docs/covers.md, \"Tighter "
        "covers for a longer bake\"); recorded in generator params.\n"
        "max_spheres / target_error: a budget, or the smallest resolution whose nerr is at "
        "most E. Lengths (vertex_tolerance, max_protrusion, cover, robust_thickness) are "
        "numbers in the mesh's units or text such as '0.003L' (a multiple of the box's "
        "largest side); another type raises InputError naming the keyword.\n"
        "solid: 'auto' (the winding number's, the robust solid when that is ambiguous), "
        "'winding' or 'robust'; robust_resolution and robust_thickness shape the robust solid "
        "(docs/baking.md: Solids).\n"
        "name: the mesh's name in errors and provenance for arrays (default 'mesh').\n"
        "The loader's warnings are issued as UserWarning. The GIL is released while baking.\n"
        "Raises InputError (a ValueError) for bad options or a bad mesh.");
  def_evaluation(
      m, "evaluate", &evaluate_py, "mesh", py::arg("solid") = "auto",
      py::arg("robust_resolution") = RobustSolidOptions{}.resolution,
      py::arg("robust_thickness") = py::none(),
      "How well spheres fit a mesh, as `medspheres eval --json` reports it, as a dict "
      "(nerr, nerr_kind, max_protrusion, mc_error, uncovered_*, surface_certificate, "
      "solid, ...).\n\n"
      "mesh: a path or (vertices, triangles); spheres: a SphereSet, an n x 4 array or a "
      "sphere-set file path.\n"
      "solid: the solid measured against: 'auto' (the one the spheres' file or SphereSet "
      "records, robust for a set baked from the robust solid; the winding number's for an "
      "array), 'winding' or 'robust'; robust_resolution and robust_thickness (a number in "
      "the mesh's units or text such as '0.01L') shape the robust solid, and by default "
      "are the recorded ones (docs/baking.md: Solids).\n"
      "The loader's warnings are listed under 'warnings'. The GIL is released while "
      "measuring.");
  m.def(
      "load_mesh",
      [](const py::object& path) {
        std::string name;
        const LoadedMesh loaded = mesh_arg(path, name);
        warn_all(loaded.warnings, name);
        py::array_t<double> v(
            {static_cast<py::ssize_t>(loaded.mesh.vertices.size()), py::ssize_t{3}});
        auto vw = v.mutable_unchecked<2>();
        for (std::size_t i = 0; i < loaded.mesh.vertices.size(); ++i)
          for (int k = 0; k < 3; ++k)
            vw(static_cast<py::ssize_t>(i), k) = loaded.mesh.vertices[i][k];
        py::array_t<std::int32_t> f(
            {static_cast<py::ssize_t>(loaded.mesh.triangles.size()), py::ssize_t{3}});
        auto fw = f.mutable_unchecked<2>();
        for (std::size_t i = 0; i < loaded.mesh.triangles.size(); ++i)
          for (int k = 0; k < 3; ++k)
            fw(static_cast<py::ssize_t>(i), k) =
                loaded.mesh.triangles[i][static_cast<std::size_t>(k)];
        return py::make_tuple(v, f);
      },
      py::arg("path"),
      "Loads a mesh as the bake does (welded, checked, oriented): (vertices n x 3 float64, "
      "triangles m x 3 int32).");
}

}  // namespace medspheres::python
