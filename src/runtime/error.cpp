#include "medspheres/error.h"

#include <utility>

namespace medspheres {

namespace {

std::string message(const std::string& file, const std::string& field, const std::string& problem) {
  if (field.empty()) return file + ": " + problem;
  if (file.empty()) return field + ": " + problem;
  return field + ": for " + file + ", " + problem;
}

}  // namespace

const char* to_string(ErrorKind kind) {
  switch (kind) {
    case ErrorKind::kFileMissing:
      return "file_missing";
    case ErrorKind::kFileUnreadable:
      return "file_unreadable";
    case ErrorKind::kMalformedFile:
      return "malformed_file";
    case ErrorKind::kNoInterior:
      return "no_interior";
    case ErrorKind::kOutOfRange:
      return "out_of_range";
    case ErrorKind::kConflict:
      return "conflict";
    case ErrorKind::kUnreachable:
      return "unreachable";
    case ErrorKind::kWriteFailed:
      return "write_failed";
    case ErrorKind::kUnsupported:
      return "unsupported";
  }
  return "unknown";
}

InputError::InputError(ErrorKind kind, std::string file, std::string field, std::string value,
                       std::string problem, std::vector<std::string> related)
    : Error(message(file, field, problem)),
      kind_(kind),
      file_(std::move(file)),
      field_(std::move(field)),
      value_(std::move(value)),
      problem_(std::move(problem)),
      related_(std::move(related)) {}

InputError::InputError(std::string source, std::string problem)
    : InputError(ErrorKind::kMalformedFile, std::move(source), std::move(problem)) {}

InputError::InputError(ErrorKind kind, std::string file, std::string problem)
    : InputError(kind, std::move(file), {}, {}, std::move(problem), {}) {}

InputError InputError::option(ErrorKind kind, std::string field, std::string value,
                              std::string problem, std::string file,
                              std::vector<std::string> related) {
  return InputError(kind, std::move(file), std::move(field), std::move(value), std::move(problem),
                    std::move(related));
}

InputError InputError::with_file(std::string file) const {
  return InputError(kind_, std::move(file), field_, value_, problem_, related_);
}

InputError InputError::with_field(std::string field) const {
  return InputError(kind_, file_, std::move(field), value_, problem_, related_);
}

}  // namespace medspheres
