#pragma once
/// \file
/// The one error policy of medspheres.
///
/// - Bad input from a user or a file throws InputError: what went wrong (ErrorKind),
///   the file and the option field at fault (named as the library's structs spell them,
///   "max_spheres"), and the offending value.
/// - A violated precondition of a function throws std::invalid_argument.
/// - Internal invariants use MEDSPHERES_ASSERT (assert.h); nothing prints and carries on.
///
/// The CLI maps kinds and fields to its flags, messages and exit codes in one place.

#include <stdexcept>
#include <string>
#include <vector>

namespace medspheres {

/// Base of every exception that medspheres throws itself.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What went wrong with the input.
enum class ErrorKind {
  kFileMissing,     ///< no such file
  kFileUnreadable,  ///< exists but cannot be read (permissions, a directory, a FIFO, ...)
  kMalformedFile,   ///< read, but not a valid file of its format
  kNoInterior,      ///< the mesh bounds no volume to put spheres in
  kOutOfRange,      ///< an option's value outside its range, or not a value of its type
  kConflict,        ///< options that do not go together
  kUnreachable,     ///< a budget or target that no setting tried reaches
  kWriteFailed,     ///< an output path that cannot be written
  kUnsupported,     ///< a request the input does not support (an error target on an open mesh)
};

/// "file_missing", "out_of_range", ...
const char* to_string(ErrorKind kind);

/// Bad input from a file or from a user.
/// what() reads "<file>: <problem>" for a file at fault, "<field>: <problem>" for an
/// option, and "<field>: for <file>, <problem>" for an option judged against a file.
class InputError : public Error {
 public:
  /// A problem of \p source (a file, or another name of what is at fault), of kind
  /// kMalformedFile. \p problem is one sentence without a trailing period.
  InputError(std::string source, std::string problem);
  /// A problem of the file \p file.
  InputError(ErrorKind kind, std::string file, std::string problem);

  /// A problem of the option \p field whose value, as text, is \p value; \p file is the
  /// file it was judged against ("" for none). \p related names the other fields the
  /// problem text mentions (the other side of a conflict, the options to change).
  static InputError option(ErrorKind kind, std::string field, std::string value,
                           std::string problem, std::string file = {},
                           std::vector<std::string> related = {});

  /// The same error, about \p file (the caller's name for what the library called "mesh").
  InputError with_file(std::string file) const;
  /// The same error, about the option \p field (for a value parsed before its field is known).
  InputError with_field(std::string field) const;

  ErrorKind kind() const noexcept { return kind_; }
  /// The file, or when there is none the field: what what() starts with.
  const std::string& source() const noexcept { return field_.empty() ? file_ : field_; }
  const std::string& file() const noexcept { return file_; }
  const std::string& field() const noexcept { return field_; }  ///< "" for a file's problem
  const std::string& value() const noexcept { return value_; }
  const std::string& problem() const noexcept { return problem_; }
  const std::vector<std::string>& related() const noexcept { return related_; }

 private:
  InputError(ErrorKind kind, std::string file, std::string field, std::string value,
             std::string problem, std::vector<std::string> related);

  ErrorKind kind_;
  std::string file_, field_, value_, problem_;
  std::vector<std::string> related_;
};

}  // namespace medspheres
