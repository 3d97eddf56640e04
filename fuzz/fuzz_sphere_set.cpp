// The sphere-set JSON reader (io.h). Oracle: what it accepts, it writes back, and the
// written text reads back to the same text (write after read is a fixed point).
#include "fuzz_support.h"
#include "medspheres/io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace medspheres;
  SphereSet set;
  if (!fuzz::accepts([&] { set = parse_sphere_set(fuzz::text_of(data, size), "fuzz.json"); }))
    return 0;
  const std::string once = sphere_set_to_json(set);
  const std::string twice = sphere_set_to_json(parse_sphere_set(once, "written.json"));
  MEDSPHERES_FUZZ_CHECK(once == twice);
  return 0;
}
