// medspheres-import: the program load_mesh starts to run assimp on one file, isolated from
// the caller (mesh_io.cpp, "Why the import is isolated"). It is started by run_isolated
// (isolated_call.h) as `medspheres-import --isolated <caller pid> <bytes> <file>`, imports
// the file and writes the flattened scene, or what went wrong, to the caller's pipe in the
// format of scene_import.h. It is not meant to be run by hand.
#include <cstdio>
#include <new>
#include <string>
#include <vector>

#include "isolated_call.h"
#include "medspheres/error.h"
#include "scene_import.h"

namespace {

std::string import_answer(const std::vector<std::string>& args) {
  using namespace medspheres;
  if (args.size() != 1) return detail::encode_message('X', "expected one file to import");
  try {
    return detail::encode_scene(detail::import_flat(args[0]));
  } catch (const InputError& e) {
    return detail::encode_message('E', e.problem());
  } catch (const std::bad_alloc&) {
    return detail::encode_message('M', "");
  } catch (const std::exception& e) {
    return detail::encode_message('X', e.what());
  }
}

}  // namespace

int main(int argc, char** argv) {
  medspheres::detail::serve_isolated(argc, argv, import_answer);
  std::fprintf(stderr,
               "medspheres-import: the mesh import process of medspheres, started by the "
               "library itself (load_mesh); it is not meant to be run by hand\n");
  return 2;
}
