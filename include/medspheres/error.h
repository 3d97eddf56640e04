#pragma once
/// \file
/// The one error policy of medspheres.
///
/// - Bad input from a user or a file (a missing file, a malformed sphere file, a mesh
///   with NaN coordinates, a mesh with no interior, ...) throws InputError. Its
///   message starts with the name of the file or the option at fault.
/// - A violated precondition of a function (a negative tolerance, a null pointer, an
///   index out of range) throws std::invalid_argument.
/// - Internal invariants use MEDSPHERES_ASSERT (see assert.h), which a build option
///   turns on.
/// - Nothing in the library prints to std::cerr and carries on.
///
/// The CLI maps InputError and std::invalid_argument to exit code 2, everything else
/// to exit code 1.

#include <stdexcept>
#include <string>

namespace medspheres {

/// Base of every exception that medspheres throws itself.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Bad input from a file or from a user. what() reads "<source>: <problem>".
class InputError : public Error {
 public:
  /// \param source the file name, or an option name such as "--resolution".
  /// \param problem what is wrong, as one sentence without a trailing period.
  InputError(std::string source, std::string problem);

  const std::string& source() const noexcept { return source_; }
  const std::string& problem() const noexcept { return problem_; }

 private:
  std::string source_;
  std::string problem_;
};

}  // namespace medspheres
