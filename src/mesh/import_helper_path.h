#pragma once
// Private: where the import helper program (medspheres-import, import_helper_main.cpp) is.

#include <string>

namespace medspheres::detail {

/// The environment variable that names the import helper, overriding the search.
constexpr const char* kImportHelperVariable = "MEDSPHERES_IMPORT_HELPER";

/// The path of the import helper: the file named by $MEDSPHERES_IMPORT_HELPER when it is
/// set and not empty; else the first executable medspheres-import found beside the
/// binary that holds this code (the program, or the shared library or Python module
/// linking it), in the install's bin folder relative to that binary's lib folder, beside
/// the running program, and in the bin folder of the install prefix the library was
/// built for.
/// \throws medspheres::Error starting with "<subject>: " that names the places looked in
///   when there is none, or the variable's value when it names no executable file.
std::string import_helper_path(const std::string& subject);

}  // namespace medspheres::detail
