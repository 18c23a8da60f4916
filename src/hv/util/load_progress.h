// Progress of the reads from services, per source (docs/services.md, "Progress"): what the
// progress lines on stderr say, kept for a display to show (the viewer's panel) and for a count at
// the end. Fed by the service fetch callback (hv/io/native/private/service_fetch.h) for every
// response of a source being loaded. Process-wide and thread-safe.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace hv {

struct SourceProgress {
  std::string what;    // "terrain", "buildings", "cameras", "the orthophoto", ...
  std::string source;  // the URL or connection string it is read from
  std::size_t responses = 0, fromCache = 0;
  std::uint64_t bytes = 0;
  std::string lastLine;  // the last progress line printed for it
};

// One response for `what` from `source` (`line`: the progress line printed for it).
void recordLoadProgress(const std::string& what, const std::string& source, std::uint64_t bytes, bool fromCache,
                        const std::string& line);
// Every source seen so far, in the order first seen.
std::vector<SourceProgress> loadProgress();
// "buildings from WFS:http://…: 5 responses, 12 KB (2 from the cache)".
std::string describeProgress(const SourceProgress& p);
// Forgets them (tests).
void clearLoadProgress();

}  // namespace hv
