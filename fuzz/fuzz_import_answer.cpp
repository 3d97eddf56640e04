// The answer of the import child (scene_import.h), the bytes load_mesh reads from the pipe:
// a truncated or malformed answer must be refused (ok false), never read past its end.
// Oracles: an accepted scene or message encodes back to the same bytes, and an accepted
// scene goes through the rest of load_mesh (welding, checks, orientation) without a crash.
#include "../src/mesh/scene_import.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace medspheres;
  const std::string bytes = fuzz::text_of(data, size);
  const detail::ImportAnswer answer = detail::decode_answer(bytes);
  if (!answer.ok) return 0;
  if (answer.tag != 'R') {
    MEDSPHERES_FUZZ_CHECK(detail::encode_message(answer.tag, answer.text) == bytes);
    return 0;
  }
  MEDSPHERES_FUZZ_CHECK(detail::encode_scene(answer.scene) == bytes);
  fuzz::accepts([&] { detail::mesh_from_scene(answer.scene, "fuzz.stl", true); });
  return 0;
}
