// Fuzz target: cameras.json / VIEWS.json parser (hv::parseCameraJson).
#include "fuzz_util.h"
#include "hv/io/cameras_json.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  hv::fuzz::expectOnlyInputErrors("cameras_json", [&] {
    for (const bool requireImages : {true, false}) {
      hv::Diagnostics diag;
      hv::CameraFileOptions options{.requireImages = requireImages, .checkImageFiles = false};
      const auto photos = hv::parseCameraJson(text, "fuzz.json", "/nonexistent", options, diag);
      // A camera that loaded passed validation; writing it back must not fail either.
      (void)hv::cameraJson(photos, "");
    }
  });
  return 0;
}
