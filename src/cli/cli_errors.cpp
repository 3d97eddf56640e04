// The one place where the library's errors become the CLI's words and exit codes.
#include <algorithm>
#include <cctype>
#include <iostream>
#include <string>

#include "cli_common.h"

namespace medspheres::cli {

namespace {

bool word_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
}

// \p text with every whole-word \p name replaced by \p flag.
std::string replace_word(std::string text, const std::string& name, const std::string& flag) {
  for (std::size_t at = text.find(name); at != std::string::npos; at = text.find(name, at)) {
    const std::size_t end = at + name.size();
    const bool whole =
        (at == 0 || !word_char(text[at - 1])) && (end == text.size() || !word_char(text[end]));
    if (!whole) {
      at = end;
      continue;
    }
    text.replace(at, name.size(), flag);
    at += flag.size();
  }
  return text;
}

}  // namespace

std::string flag_of(std::string field) {
  std::replace(field.begin(), field.end(), '_', '-');
  return "--" + field;
}

std::string message_of(const InputError& e) {
  std::string problem = e.problem();
  for (const std::string& name : e.related()) problem = replace_word(problem, name, flag_of(name));
  if (e.field().empty()) return e.file() + ": " + problem;
  const std::string flag = flag_of(e.field());
  if (e.file().empty()) return flag + ": " + problem;
  return flag + ": for " + e.file() + ", " + problem;
}

int exit_code_of(ErrorKind) {
  return kExitBadInput;  // every kind is bad input or a bad request
}

int report_input_error(const InputError& e) {
  std::cerr << "medspheres: error: " << message_of(e) << "\n";
  return exit_code_of(e.kind());
}

}  // namespace medspheres::cli
