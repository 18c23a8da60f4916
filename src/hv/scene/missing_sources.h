// What a scene lacks (docs/services.md, "What is missing"): the sources, tiles and photographs
// that were asked for and could not be read, each with where it was asked from and why. The frame
// renders with what has arrived; this list says what has not. Filled by the scene loader (a
// terrain, buildings, cameras, orthophoto or points source left out; a photograph whose IIIF
// description failed; a point tile) and by the streaming parts while frames render (a building
// tile that failed, with its retry; a photograph whose image could not be read). `histoview
// render`, `fly` and `info` print it, the viewer's panel lists it.
//
// Thread-safe: the loader's threads, the renderer's thread and the viewer read and write it at
// once. Shared by the copies of a scene (Scene::missing).
#pragma once

#include <cstddef>
#include <mutex>
#include <string>
#include <vector>

namespace hv {

struct MissingSource {
  std::string kind;      // "terrain", "buildings", "building tile", "cameras", "orthophoto", "photograph", ...
  std::string location;  // the URL, connection string or path asked for (a tile: the source's, and the tile)
  std::string reason;    // what went wrong (the message, without a leading "location: ")
  bool retrying = false;  // it will be asked for again (a building tile waiting for its next try)
  int attempts = 1;       // tries so far (the caller counts them)
  bool operator==(const MissingSource& o) const = default;
};

class MissingSources {
 public:
  // Records `s`. An entry of the same kind and location is replaced, so that a tile failing again
  // (or a source read twice) is one entry. A reason starting with the location and ": " loses it.
  void add(MissingSource s);
  // The entry of that kind and location arrived after all: removed. False when there was none.
  bool resolve(const std::string& kind, const std::string& location);
  void clear();

  std::vector<MissingSource> list() const;  // in the order first recorded
  std::size_t size() const;
  bool empty() const { return size() == 0; }
  // Bumped by every change, for a display to redraw only when something changed.
  std::size_t version() const;

  // One line per entry: "buildings: WFS:http://…: HTTP error code : 404 (retrying, 2 tries)".
  std::vector<std::string> lines() const;
  // One line for all: "missing: buildings (WFS:http://…), 2 photographs, 1 building tile"; kinds
  // with one entry name its location, kinds with more count them; "" when nothing is missing.
  std::string summary() const;

 private:
  mutable std::mutex mutex_;
  std::vector<MissingSource> items_;
  std::size_t version_ = 0;
};

// "location: reason (retrying, N tries)" for one entry (MissingSources::lines without the kind).
std::string describeMissing(const MissingSource& s);

}  // namespace hv
