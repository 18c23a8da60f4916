#include "hv/session/checks.h"

#include "hv/io/native/georef.h"
#include "hv/scene/robust_extent.h"
#include "hv/util/dates.h"
#include "hv/util/input_file.h"

#include <stb_image.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

namespace hv::app {

namespace fs = std::filesystem;

namespace {

std::string megabytes(std::size_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB"; }

const char* levelName(CheckItem::Level l) {
  return l == CheckItem::Level::Problem ? "problem" : l == CheckItem::Level::Warning ? "warning" : "note";
}

}  // namespace

CLI::Validator positiveCount() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        long long v = 0;
        std::istringstream in(text);
        in >> v;
        if (in && (in >> std::ws).eof() && v >= 1) return "";
        return "expected a whole number of at least 1, got '" + text + "'";
      },
      "N");
}

glm::ivec2 nearestValidViewSize(int width, int height, int maxTextureSize) {
  double s = 1.0;
  if (maxTextureSize > 0) s = std::min({s, double(maxTextureSize) / width, double(maxTextureSize) / height});
  s = std::min(s, std::sqrt(double(kMaxViewPixels) / (double(width) * double(height))));
  // Rounded down, so the size found is within both limits; the aspect ratio within a pixel.
  return {std::max(1, int(std::floor(width * s))), std::max(1, int(std::floor(height * s)))};
}

std::string viewSizeProblem(const Camera& view, int maxTextureSize) {
  const std::string size = std::to_string(view.width) + "x" + std::to_string(view.height);
  const glm::ivec2 valid = nearestValidViewSize(view.width, view.height, maxTextureSize);
  const std::string hint = "; the nearest size that fits, same aspect ratio: --size " + std::to_string(valid.x) + "x" +
                           std::to_string(valid.y);
  if (maxTextureSize > 0 && (view.width > maxTextureSize || view.height > maxTextureSize))
    return "the view is " + size + ", larger than the context's MAX_TEXTURE_SIZE (" + std::to_string(maxTextureSize) +
           ")" + hint;
  if (std::int64_t(view.width) * view.height > kMaxViewPixels)
    return "the view is " + size + " (" + std::to_string(std::int64_t(view.width) * view.height / 1000000) +
           " megapixels), more than the limit of " + std::to_string(kMaxViewPixels / 1000000) +
           " megapixels whose buffers fit in memory" + hint;
  return "";
}

namespace {
// The first MiB of a local image file (the header and marker segments stb_image parses before the
// size fields); sets h.fileBytes.
std::vector<std::uint8_t> readLocalHead(const std::string& path, ImageHeader& h) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) throw InputError(inputMessage(path, "", "not found"));
  if (!fs::is_regular_file(st)) throw InputError(inputMessage(path, "", "not a regular file (expected a JPEG or PNG)"));
  h.fileBytes = fs::file_size(path, ec);
  if (ec) throw InputError(inputMessage(path, "", "cannot read the file size: " + ec.message()));
  if (h.fileBytes > std::uintmax_t(std::numeric_limits<int>::max()))
    throw InputError(inputMessage(path, "", "file of " + std::to_string(h.fileBytes) + " bytes, more than 2 GiB"));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(inputMessage(path, "", "cannot open the file"));
  // The header and marker segments stb_image parses before the size fields: the first MiB.
  std::vector<std::uint8_t> head(std::size_t(std::min<std::uintmax_t>(h.fileBytes, 1u << 20)));
  if (!in.read(reinterpret_cast<char*>(head.data()), std::streamsize(head.size())))
    throw InputError(inputMessage(path, "", "read error"));
  return head;
}
}  // namespace

ImageHeader probeImageFile(const std::string& path) {
  ImageHeader h;
  std::vector<std::uint8_t> head;
  if (isHttpUrl(path)) {
    // The whole response (from the response cache when it holds it): HTTP has no cheap header read.
    head = readInputBytes(path, kMaxImageBytes, "", RemoteCache::Yes);
    h.fileBytes = head.size();
    head.resize(std::min<std::size_t>(head.size(), 1u << 20));
  } else {
    head = readLocalHead(path, h);
  }
  checkImageBytes(head.data(), head.size(), path, head.size() == h.fileBytes);
  if (!stbi_info_from_memory(head.data(), int(head.size()), &h.width, &h.height, &h.channels) || h.width <= 0 ||
      h.height <= 0) {
    const char* why = stbi_failure_reason();
    throw InputError(inputMessage(
        path, "",
        std::string("cannot read the image size (expected a JPEG or PNG): ") + (why ? why : "unknown error")));
  }
  const bool is16 = stbi_is_16_bit_from_memory(head.data(), int(head.size())) != 0;
  // ImageLoader's bound for one file (hv/ibr/image_loader.cpp): three copies of the file, four
  // 4-channel planes padded to whole 16-pixel blocks, the copy handed back.
  const std::size_t padded = std::size_t(h.width + 16) * std::size_t(h.height + 16);
  h.decodeBytes = 3 * std::size_t(h.fileBytes) + 16 * padded * (is16 ? 2 : 1) +
                  std::size_t(h.width) * std::size_t(h.height) * std::size_t(h.channels);
  return h;
}

Image8 decodeImageCapped(const std::string& path, std::size_t capBytes, int wantChannels) {
  const ImageHeader h = probeImageFile(path);
  if (h.decodeBytes > capBytes)
    throw InputError(inputMessage(path, "",
                                  "a " + std::to_string(h.width) + "x" + std::to_string(h.height) +
                                      " image: decoding it needs about " + megabytes(h.decodeBytes) +
                                      ", more than the limit of " + megabytes(capBytes)));
  const std::vector<std::uint8_t> bytes =
      isHttpUrl(path) ? readInputBytes(path, kMaxImageBytes, "", RemoteCache::Yes) : readFileBytes(path);
  if (bytes.size() != h.fileBytes) throw InputError(inputMessage(path, "", "the file changed while it was read"));
  return decodeImage(bytes.data(), bytes.size(), path, wantChannels);
}

std::size_t CheckReport::problems() const {
  return std::size_t(std::count_if(items.begin(), items.end(),
                                   [](const CheckItem& i) { return i.level == CheckItem::Level::Problem; }));
}

std::string CheckReport::text() const {
  std::map<std::string, std::vector<const CheckItem*>> byKind;
  for (const CheckItem& i : items) byKind[i.kind].push_back(&i);
  std::ostringstream s;
  for (const auto& [kind, list] : byKind) {
    s << kind << "\n";
    for (const CheckItem* i : list) s << "  " << levelName(i->level) << ": " << i->message << "\n";
  }
  s << photographs << " photograph(s) and " << masks << " mask(s) checked; " << problems()
    << " item(s) would be left out or refused\n";
  return s.str();
}

nlohmann::json CheckReport::json() const {
  nlohmann::json j;
  j["photographs"] = photographs;
  j["masks"] = masks;
  j["problems"] = problems();
  j["items"] = nlohmann::json::array();
  for (const CheckItem& i : items)
    j["items"].push_back({{"kind", i.kind}, {"level", levelName(i.level)}, {"message", i.message}});
  return j;
}

CheckReport checkScene(const Scene& scene, const Diagnostics& loadDiag, const CheckOptions& options) {
  CheckReport report;
  auto add = [&](const std::string& kind, CheckItem::Level level, std::string message) {
    report.items.push_back({kind, level, std::move(message)});
  };
  // What the loader left out (errors) and warned about, as it said it.
  for (const std::string& e : loadDiag.errors) add("scene", CheckItem::Level::Problem, e);
  for (const std::string& w : loadDiag.warnings) add("scene", CheckItem::Level::Warning, w);

  if (scene.photos.empty())
    add("cameras", CheckItem::Level::Warning,
        scene.path + ": no photograph loaded: every view shows the geometry untextured");
  std::map<std::string, int> ids;
  for (const Photo& p : scene.photos)
    if (++ids[p.camera.id] == 2)
      add("cameras", CheckItem::Level::Warning,
          "camera '" + p.camera.id + "': duplicate id (--exclude, --debug and file names cannot tell them apart)");

  // Photographs and masks: headers always, full decodes with `deep`, on worker threads.
  struct Result {
    std::vector<CheckItem> items;
    bool mask = false;
  };
  std::vector<Result> results(scene.photos.size());
  std::atomic<size_t> next{0};
  std::atomic<int> done{0};
  std::mutex progressMutex;
  auto checkOne = [&](size_t i) {
    const Photo& p = scene.photos[i];
    Result& r = results[i];
    const std::string who = "camera '" + p.camera.id + "'";
    auto problem = [&](const std::string& kind, const std::string& m) {
      r.items.push_back({kind, CheckItem::Level::Problem, m + " (the photograph would be left out)"});
    };
    if (p.imagePath.empty()) return problem("photographs", who + ": image: no file given");
    ImageHeader image;
    try {
      image = probeImageFile(p.imagePath);
      if (options.deep) decodeImageCapped(p.imagePath, options.capBytes);
      const double aspectCam = double(p.camera.width) / p.camera.height;
      if (std::abs(double(image.width) / image.height - aspectCam) > 0.01 * aspectCam)
        return problem("photographs",
                       inputMessage(p.imagePath, who,
                                    "the image is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                                        ", expected the camera's " + std::to_string(p.camera.width) + "x" +
                                        std::to_string(p.camera.height) + " (or the same aspect ratio)"));
    } catch (const std::exception& e) {
      return problem("photographs", who + ": image: " + e.what());
    }
    if (p.maskPath.empty()) return;
    r.mask = true;
    try {
      const ImageHeader mask = probeImageFile(p.maskPath);
      if (options.deep) decodeImageCapped(p.maskPath, options.capBytes, 1);
      const std::string sizes = "the mask is " + std::to_string(mask.width) + "x" + std::to_string(mask.height) +
                                ", the photograph " + std::to_string(image.width) + "x" + std::to_string(image.height);
      const double aspect = double(image.width) / image.height;
      if (std::abs(double(mask.width) / mask.height - aspect) > 0.01 * aspect)
        problem("masks", inputMessage(p.maskPath, who + ": mask", sizes + " (expected the same aspect ratio)"));
      else if (mask.width != image.width || mask.height != image.height)
        r.items.push_back({"masks", CheckItem::Level::Warning,
                           inputMessage(p.maskPath, who + ": mask", sizes + " (same aspect ratio: resampled)")});
    } catch (const std::exception& e) {
      problem("masks", who + ": mask: " + e.what());
    }
  };
  auto worker = [&] {
    for (size_t i = next++; i < results.size(); i = next++) {
      checkOne(i);
      const int d = ++done;
      if (options.progress) {
        const std::lock_guard<std::mutex> lock(progressMutex);
        options.progress(d, int(results.size()));
      }
    }
  };
  const int threads = options.deep ? std::max(1, options.threads) : 1;
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  for (const Result& r : results) {
    report.items.insert(report.items.end(), r.items.begin(), r.items.end());
    ++report.photographs;
    report.masks += r.mask;
  }

  for (const std::string& o : robustExtent(scene).outliers) add("coordinates", CheckItem::Level::Warning, o);
  for (const Photo& p : scene.photos)
    if (!p.date.empty() && !parseDate(p.date))
      add("dates", CheckItem::Level::Warning,
          "camera '" + p.camera.id + "': date: expected an ISO 8601 date (YYYY, YYYY-MM, YYYY-MM-DD...), got '" +
              p.date + "' (treated as undated)");
  if (!scene.crs.empty()) {
    try {
      add("crs", CheckItem::Level::Note, "scene: " + describeCrs(scene.crs).summary());
    } catch (const std::exception& e) {
      add("crs", CheckItem::Level::Problem, scene.path + ": crs: " + e.what());
    }
  }
  for (const Scene::SourceCrs& s : scene.sourceCrs)
    add("crs", CheckItem::Level::Note,
        s.source + (s.transformed ? " from " : " in ") + s.crs +
            (s.transformed ? "" : " (taken as it is: the scene declares no crs)"));
  return report;
}

}  // namespace hv::app
