#include "hv/util/load_progress.h"

#include <mutex>

namespace hv {
namespace {

std::mutex gMutex;
std::vector<SourceProgress>& sources() {
  static std::vector<SourceProgress> s;
  return s;
}

std::string bytesText(std::uint64_t b) {
  if (b < 10 * 1024) return std::to_string(b) + " bytes";
  if (b < 10ull * 1024 * 1024) return std::to_string(b / 1024) + " KB";
  return std::to_string(b / (1024 * 1024)) + " MB";
}

}  // namespace

void recordLoadProgress(const std::string& what, const std::string& source, std::uint64_t bytes, bool fromCache,
                        const std::string& line) {
  const std::lock_guard<std::mutex> lock(gMutex);
  std::vector<SourceProgress>& all = sources();
  SourceProgress* p = nullptr;
  for (SourceProgress& s : all)
    if (s.what == what && s.source == source) p = &s;
  if (!p) {
    all.push_back({what, source});
    p = &all.back();
  }
  ++p->responses;
  p->fromCache += fromCache;
  p->bytes += bytes;
  p->lastLine = line;
}

std::vector<SourceProgress> loadProgress() {
  const std::lock_guard<std::mutex> lock(gMutex);
  return sources();
}

std::string describeProgress(const SourceProgress& p) {
  std::string out = p.what + " from " + p.source + ": " + std::to_string(p.responses) +
                    (p.responses == 1 ? " response, " : " responses, ") + bytesText(p.bytes);
  if (p.fromCache) out += " (" + std::to_string(p.fromCache) + " from the cache)";
  return out;
}

void clearLoadProgress() {
  const std::lock_guard<std::mutex> lock(gMutex);
  sources().clear();
}

}  // namespace hv
