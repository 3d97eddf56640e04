#pragma once
/// \file
/// number_text: the one way medspheres writes a number for people (messages, CLI output).

#include <cstddef>
#include <string>

namespace medspheres {

/// \p v with up to \p digits significant digits, as printf's "%.<digits>g" in the "C"
/// locale ("0.25", "1e-09", "inf", "nan"). Thread-safe and lock-free (no stream, no
/// locale), so it may run where streams may not (mesh_io.h, "Threads").
std::string number_text(double v, int digits = 6);

/// The shortest text of \p v that reads back to the same double ("0.1", "1e-300"): what
/// the files write. Thread-safe and lock-free.
std::string exact_number_text(double v);

/// "\p n \p noun" with the noun in the plural unless \p n is 1: count_text(1, "link") is
/// "1 link", count_text(0, "link") "0 links", count_text(2, "vertex", "vertices") "2 vertices".
/// \p plural defaults to \p noun + "s".
std::string count_text(std::size_t n, const std::string& noun, const std::string& plural = "");

}  // namespace medspheres
