// Per-tile image lists (ibr/tile_culling.h): the GPU reduces each tile of the view depth to its
// depth range, the CPU lists the images whose frustum may cover each tile's slab, and the lists go
// to an R16UI texture that the shading loop walks.
#include "hv/render/gl/gl_backend.h"

#include "hv/gpu/textures.h"
#include "hv/ibr/tile_culling.h"

#include <algorithm>

namespace hv::render::gl {

// Leaves viewFbo bound. Turns culling off for the frame when the list texture would not fit.
void GlBackend::tileListPass(const Frame& f, ViewPassStats& stats) {
  ibr::TileGrid grid;
  grid.tileSize = f.tileSize;
  grid.depthSize = f.rect.depthSize;
  grid.rect = f.rect.frustum;
  const glm::ivec2 tiles(grid.tilesX(), grid.tilesY());
  if (tiles != tileRangeSize_) {
    tileRange_ = gpu::makeRgba8Target(tiles.x, tiles.y);
    tileRangeSize_ = tiles;
  }
  gpu::attachDepth(0);
  gpu::attachColour(tileRange_.id());
  gpu::drawToColour();
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  gpu::checkFramebuffer("tile depth ranges");
  glViewport(0, 0, tiles.x, tiles.y);
  tileDepthProgram_.program.use();
  gpu::bindUnit(kUnitViewDepth, GL_TEXTURE_2D, viewDepth_.id());
  glUniform1i(tileDepthProgram_.viewDepth, kUnitViewDepth);
  glUniform2i(tileDepthProgram_.depthSize, f.rect.depthSize.x, f.rect.depthSize.y);
  glUniform1i(tileDepthProgram_.tileSize, grid.tileSize);
  gpu::drawFullscreen(emptyVao_);
  std::vector<std::uint8_t> rgba(size_t(tiles.x) * tiles.y * 4);
  glReadPixels(0, 0, tiles.x, tiles.y, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  gpu::checkGlError("tile depth ranges");

  const ibr::TileLists lists =
      ibr::buildTileLists(f.view, f.origin, grid, ibr::decodeTileDepth(rgba, grid), f.params);
  stats.tileListsBuilt = true;
  stats.meanTileList = lists.meanCount();
  stats.maxTileList = lists.maxCount();
  const int width = lists.maxCount() + 1, rows = tiles.x * tiles.y;
  if (width > limits_.maxTextureSize || rows > limits_.maxTextureSize) {
    diag_.warn("per-tile culling needs a " + std::to_string(width) + "x" + std::to_string(rows) +
               " list texture, beyond MAX_TEXTURE_SIZE; this frame loops over every image");
    cullingThisFrame_ = false;
    return;
  }
  std::vector<std::uint16_t> table(size_t(width) * rows, 0);
  for (int t = 0; t < rows; ++t) {
    const auto& l = lists.lists[size_t(t)];
    table[size_t(t) * width] = std::uint16_t(l.size());
    std::copy(l.begin(), l.end(), table.begin() + std::ptrdiff_t(size_t(t) * width + 1));
  }
  tileLists_ = gpu::makeTexture();
  glBindTexture(GL_TEXTURE_2D, tileLists_.id());  // uploaded on unit 0, bound to its unit for the shading pass
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R16UI, width, rows, 0, GL_RED_INTEGER, GL_UNSIGNED_SHORT, table.data());
  gpu::setNearestClamp(GL_TEXTURE_2D);
  tilesX_ = tiles.x;
  gpu::checkGlError("tile lists");
}

}  // namespace hv::render::gl
