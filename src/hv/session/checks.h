// Scene checks (`histoview check`, and the start of `histoview info`) and the checks of option
// values and view sizes that every rendering command shares (docs/reliability.md).
#pragma once

#include "hv/camera/camera.h"
#include "hv/image/image.h"
#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace CLI {
class Validator;
}

namespace hv::app {

// A whole number >= 1 (--k and the other counts): CLI11 names the option, the message the value,
// where CLI11's PositiveNumber prints a 309-digit range.
CLI::Validator positiveCount();

// The largest view a command renders: its colour, coverage and count buffers (about 16 bytes a
// pixel with the GL copies) must fit comfortably in memory. 64 megapixels, e.g. 8192 x 8192.
inline constexpr std::int64_t kMaxViewPixels = std::int64_t(1) << 26;
// Empty when `view` can be rendered; otherwise a sentence naming its size and the limit it
// exceeds (MAX_TEXTURE_SIZE of the context, or kMaxViewPixels).
std::string viewSizeProblem(const Camera& view, int maxTextureSize);
// The largest size of the same aspect ratio (within a pixel) that viewSizeProblem accepts: the
// size named by its message.
glm::ivec2 nearestValidViewSize(int width, int height, int maxTextureSize);

// What an image file's header says (nothing decoded).
struct ImageHeader {
  int width = 0, height = 0, channels = 0;
  std::uintmax_t fileBytes = 0;
  // Peak bytes a full decode allocates (the bound ImageLoader reserves for the file alone).
  std::size_t decodeBytes = 0;
};
// Probes `path`: a regular file (a FIFO or device is refused without being opened, so nothing
// blocks), a JPEG or PNG signature, marker segments stb_image can parse, the size. Throws
// InputError naming the file.
ImageHeader probeImageFile(const std::string& path);
// Decodes `path` after probing it, refusing (InputError naming the size and the cap) a file whose
// decode would allocate more than `capBytes`: the renderer's loader cap, so that what a command
// publishes or checks is what the renderer would load.
Image8 decodeImageCapped(const std::string& path, std::size_t capBytes, int wantChannels = 0);

// One finding of the scene checks.
struct CheckItem {
  enum class Level { Problem, Warning, Note };
  std::string kind;     // "scene", "cameras", "photographs", "masks", "coordinates", "dates", "crs"
  Level level = Level::Note;
  std::string message;  // file, field and expectation
};

struct CheckReport {
  std::vector<CheckItem> items;
  int photographs = 0, masks = 0;  // probed (or decoded, deep)
  // Items whose level is Problem: inputs that would be left out or refused.
  std::size_t problems() const;
  std::string text() const;        // grouped by kind
  nlohmann::json json() const;
};

struct CheckOptions {
  bool deep = false;                  // decode every photograph and mask fully
  int threads = 2;                    // deep decodes in parallel
  std::size_t capBytes = std::size_t(512) << 20;  // per decode (the loader's default cap)
  std::function<void(int done, int total)> progress;  // deep: after each photograph
};

// Checks a loaded scene: what the loader reported (`loadDiag`: errors are items left out), each
// camera's id (duplicates), each photograph's and mask's header (or full decode), masks whose
// size or aspect ratio differs from the photograph's, outlying coordinates (hv/scene/robust_extent.h),
// dates that are not ISO 8601, the CRSs of the sources.
CheckReport checkScene(const Scene& scene, const Diagnostics& loadDiag, const CheckOptions& options = {});

}  // namespace hv::app
