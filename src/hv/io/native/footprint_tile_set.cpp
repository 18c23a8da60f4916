// Buildings as tiles read on demand (hv/io/native/footprints.h, footprintTileSet) and the one
// extrusion both the whole load and the streamed tiles go through (extrudeFootprintTile).
#include "hv/io/native/footprints.h"

#include <algorithm>
#include <atomic>
#include <map>
#include <mutex>
#include <vector>
#include <stdexcept>
#include <string>
#include <thread>

namespace hv {

BuildingTileData extrudeFootprintTile(const std::vector<Footprint>& footprints, const Heightfield* dtm,
                                      const FootprintFields& fields, const std::string& path, Diagnostics& diag) {
  BuildingTileData out;
  out.mesh = buildLod1(footprints, dtm, diag);
  out.validity = footprintValidity(footprints, fields.validFrom.value_or("valid_from"),
                                   fields.validTo.value_or("valid_to"), path, diag);
  return out;
}

std::vector<BuildingTileData> extrudeFootprintTiles(const std::vector<std::vector<Footprint>>& tiles,
                                                    const Heightfield* dtm, const FootprintFields& fields,
                                                    const std::string& path, Diagnostics& diag, int threads) {
  std::vector<BuildingTileData> out(tiles.size());
  std::vector<Diagnostics> diags(tiles.size());
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t t = next++; t < tiles.size(); t = next++)
      out[t] = extrudeFootprintTile(tiles[t], dtm, fields, path, diags[t]);
  };
  if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
  const std::size_t helpers = std::min(std::size_t(threads), tiles.size()) - (tiles.empty() ? 0 : 1);
  std::vector<std::thread> pool;
  for (std::size_t i = 0; i < helpers; ++i) pool.emplace_back(work);
  work();  // this thread takes its share
  for (std::thread& t : pool) t.join();
  for (const Diagnostics& d : diags) diag.merge(d);
  return out;
}

std::shared_ptr<const BuildingTileSet> footprintTileSet(const std::string& path, const FootprintFields& fields,
                                                        const SourceGeoref& georef, const FootprintTileOptions& options,
                                                        std::shared_ptr<const Heightfield> dtm, double zlo, double zhi,
                                                        FootprintTileSource& info, Diagnostics& diag) {
  auto set = std::make_shared<BuildingTileSet>();
  set->source = path;
  // First the grid: every tile's box, nothing read through a spatial filter.
  FootprintTileOptions grid = options;
  grid.wanted = [&](glm::dvec2 lo, glm::dvec2 hi) {
    // Widened by a tile on each side: a building crossing a border reaches into the neighbours.
    const glm::dvec2 pad = glm::max(hi - lo, glm::dvec2(0.0));
    Aabb box;
    box.lo = {lo - pad, zlo};
    box.hi = {hi + pad, zhi};
    set->boxes.push_back(box);
    return false;
  };
  info = readFootprintTiles(
      path, fields, georef, grid, [](FootprintTile&) {}, diag);
  info.tilesRead = 0;
  const FootprintTileOptions tileOptions = [&] {
    FootprintTileOptions o = options;
    o.wanted = nullptr;
    return o;
  }();
  if (info.spatialFilter) {
    // One tile at a time through the spatial filter, on whichever thread asks: each reading thread
    // takes an open reader from the pool (a dataset and its layers' transforms, opened once: not
    // again for every tile) and gives it back; a GDAL dataset is never used by two threads at once,
    // and the pool holds at most one reader per thread that reads at the same time.
    struct ReaderPool {
      std::mutex mutex;
      std::vector<std::unique_ptr<FootprintTileReader>> idle;
    };
    auto pool = std::make_shared<ReaderPool>();
    set->read = [path, fields, georef, tileOptions, dtm, pool, count = set->boxes.size()](std::uint32_t tile) {
      if (tile >= count)
        throw std::out_of_range(path + ": building tile " + std::to_string(tile) + " of " + std::to_string(count));
      std::unique_ptr<FootprintTileReader> reader;
      {
        const std::lock_guard<std::mutex> lock(pool->mutex);
        if (!pool->idle.empty()) {
          reader = std::move(pool->idle.back());
          pool->idle.pop_back();
        }
      }
      if (!reader) reader = std::make_unique<FootprintTileReader>(path, fields, georef, tileOptions);
      Diagnostics diag;
      std::vector<Footprint> footprints = reader->read(tile, diag);
      {
        // A reader whose reading threw is dropped with it (closed), not given back.
        const std::lock_guard<std::mutex> lock(pool->mutex);
        pool->idle.push_back(std::move(reader));
      }
      if (!diag.errors.empty()) throw std::runtime_error(diag.errors.front());
      BuildingTileData data = extrudeFootprintTile(footprints, dtm.get(), fields, path, diag);
      data.warnings = std::move(diag.warnings);
      return data;
    };
  } else {
    // No spatial index: read once, the footprints kept by tile (the grid's warnings already said).
    auto byTile = std::make_shared<std::map<std::size_t, std::vector<Footprint>>>();
    Diagnostics quiet;
    readFootprintTiles(
        path, fields, georef, tileOptions,
        [&](FootprintTile& t) {
          auto& into = (*byTile)[t.index];
          for (Footprint& f : t.footprints) into.push_back(std::move(f));
        },
        quiet);
    // The features' warnings come with this reading (the grid's skipped them), bar those both said.
    for (std::string& w : quiet.warnings)
      if (std::find(diag.warnings.begin(), diag.warnings.end(), w) == diag.warnings.end()) diag.warn(std::move(w));
    for (std::string& e : quiet.errors) diag.error(std::move(e));
    set->read = [byTile, fields, path, dtm, count = set->boxes.size()](std::uint32_t tile) {
      if (tile >= count)
        throw std::out_of_range(path + ": building tile " + std::to_string(tile) + " of " + std::to_string(count));
      static const std::vector<Footprint> kNone;
      const auto it = byTile->find(tile);
      Diagnostics diag;
      BuildingTileData data =
          extrudeFootprintTile(it == byTile->end() ? kNone : it->second, dtm.get(), fields, path, diag);
      data.warnings = std::move(diag.warnings);
      return data;
    };
  }
  return set;
}

}  // namespace hv
