#include "number_text.h"

#include "medspheres/number_text.h"

#include <charconv>
#include <system_error>

namespace medspheres::formats {

std::string exact_numbers(const std::vector<double>& values) {
  std::string out;
  for (std::size_t i = 0; i < values.size(); ++i)
    out += (i ? " " : "") + exact_number_text(values[i]);
  return out;
}

std::optional<std::vector<double>> parse_numbers(std::string_view text) {
  std::vector<double> out;
  const char* p = text.data();
  const char* end = p + text.size();
  auto space = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
  while (true) {
    while (p < end && space(*p)) ++p;
    if (p == end) return out;
    if (*p == '+' && ++p < end && *p == '-') return std::nullopt;  // from_chars takes no '+'
    double v = 0;
    const auto [next, ec] = std::from_chars(p, end, v);
    if (ec != std::errc() || (next < end && !space(*next))) return std::nullopt;
    out.push_back(v);
    p = next;
  }
}

}  // namespace medspheres::formats
