// Fuzz target: the colour corrections file (hv::parseColourCorrections), applied to a scene's
// photographs and written back.
#include "fuzz_util.h"
#include "hv/io/colour_corrections_json.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  hv::fuzz::expectOnlyInputErrors("colour_corrections", [&] {
    hv::Diagnostics diag;
    const auto entries = hv::parseColourCorrections(text, "fuzz.json", diag);
    std::vector<hv::Photo> photos(2);
    photos[0].camera.id = "p001";
    photos[1].camera.id = "p002";
    hv::applyColourCorrections(photos, entries, "fuzz.json", diag);
    // What loaded is within the documented bounds, and writing it back must not fail.
    for (const auto& e : entries)
      for (int c = 0; c < 3; ++c)
        if (!(e.colour.gain[c] >= 0.0 && e.colour.gain[c] <= hv::kMaxColourGain &&
              e.colour.offset[c] >= -hv::kMaxColourOffset && e.colour.offset[c] <= hv::kMaxColourOffset))
          __builtin_trap();
    (void)hv::colourCorrectionsJson(entries);
  });
  return 0;
}
