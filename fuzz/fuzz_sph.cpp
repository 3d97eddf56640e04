// The .sph reader (formats/sph_file.h): every level it accepts writes back to a fixed point.
#include "fuzz_support.h"
#include "medspheres/formats/sph_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace medspheres;
  std::vector<std::vector<Sphere>> levels;
  if (!fuzz::accepts(
          [&] { levels = formats::parse_sph_levels(fuzz::text_of(data, size), "fuzz.sph"); }))
    return 0;
  for (const std::vector<Sphere>& level : levels) {
    std::string once;
    if (!fuzz::accepts([&] { once = formats::sph_text(level); })) continue;
    const std::vector<std::vector<Sphere>> back = formats::parse_sph_levels(once, "written.sph");
    MEDSPHERES_FUZZ_CHECK(!back.empty());
    MEDSPHERES_FUZZ_CHECK(formats::sph_text(back.back()) == once);
  }
  return 0;
}
