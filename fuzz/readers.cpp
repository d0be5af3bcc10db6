// libFuzzer targets for treeskel's readers, one binary per reader (chosen at compile time by
// TREESKEL_FUZZ_READER): ply, las, xyz, skeleton_ply, skeleton_json. Each feeds the bytes to the
// reader as a file's content; an InputError is the expected answer to bad bytes, anything else (a
// crash, a hang, a sanitizer report, another exception) is a finding. Built by scripts/fuzz.sh.
#include "formats.h"
#include "treeskel/error.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  using namespace treeskel::io::detail;
  try {
#if TREESKEL_FUZZ_READER == 1
    read_ply(bytes, "fuzz.ply");
#elif TREESKEL_FUZZ_READER == 2
    read_las(bytes, "fuzz.las");
#elif TREESKEL_FUZZ_READER == 3
    read_xyz(bytes, "fuzz.xyz");
#elif TREESKEL_FUZZ_READER == 4
    read_skeleton_ply(bytes, "fuzz.ply");
#elif TREESKEL_FUZZ_READER == 5
    read_skeleton_json(bytes, "fuzz.json");
#else
#error "TREESKEL_FUZZ_READER must be 1 to 5"
#endif
  } catch (const treeskel::InputError&) {
  }
  return 0;
}
