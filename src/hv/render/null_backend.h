// A backend that draws nothing and records what it was asked (the frame logic's test double, in
// the spirit of a renderer's "null" backend): the frame builder runs unchanged on the CPU, and a
// test reads back which images were uploaded to which slot, which depth maps were drawn and what
// each frame asked of the view passes.
#pragma once

#include "hv/render/backend.h"

#include <map>
#include <vector>

namespace hv::render {

class NullBackend final : public Backend {
 public:
  struct Upload {
    int slot = -1;
    int width = 0, height = 0;
  };

  explicit NullBackend(BackendLimits limits = {}) : limits_(limits) {}

  BackendLimits limits() const override { return limits_; }
  void uploadGeometry(const GeometryBuffers& geometry) override;
  void uploadStreamedTile(std::uint64_t id, const std::vector<float>& vertices,
                         const std::vector<std::uint32_t>& indices) override {
    streamedTiles[id] = int(indices.size() / 3);
    (void)vertices;
  }
  void releaseStreamedTile(std::uint64_t id) override { streamedTiles.erase(id); }
  void uploadValidity(const std::vector<float>& texels, int width, int rows) override {
    validity = texels;
    validityWidth = width;
    validityRows = rows;
    ++validityUploads;
  }
  void uploadOrthophoto(const Orthophoto& o, const OrthophotoAffine& a) override {
    orthophotoSize = {o.width, o.height};
    orthophotoAffine = a;
  }
  PointProgramInfo uploadPoints(const std::vector<PointVertex>& points, const PointProgramRequest& req) override;
  void allocateSlots(const SlotLayout& layout) override { layout_ = layout; }
  void uploadImage(int slot, const Image8& slice) override { uploads.push_back({slot, slice.width, slice.height}); }
  void drawDepthMap(const DepthMapJob& job) override { depthMaps.push_back(job); }
  void uploadDepthMap(int slot, const std::vector<float>& depth) override { depthUploads.push_back({slot, depth}); }
  void finishDepthMaps() override { ++finishes; }
  RenderOutput runViewPasses(const Frame& frame, ViewPassStats& stats) override;
  unsigned int colorTexture() const override { return 0; }

  // What was asked, in order.
  std::vector<Upload> uploads;
  std::vector<DepthMapJob> depthMaps;
  struct DepthUpload {
    int slot = -1;
    std::vector<float> depth;
  };
  std::vector<DepthUpload> depthUploads;  // maps filled by uploadDepthMap
  std::vector<Frame> frames;              // one per runViewPasses
  int finishes = 0;
  int triangles = 0;                          // uploaded geometry
  GeometryBuffers geometry;                   // as uploaded
  std::map<std::uint64_t, int> streamedTiles;  // streamed tiles held: id -> triangles
  std::vector<float> validity;                 // the building validity texels, as last uploaded
  int validityWidth = 1, validityRows = 1, validityUploads = 0;
  glm::ivec2 orthophotoSize{0};  // as uploaded (0: none)
  OrthophotoAffine orthophotoAffine;
  std::size_t points = 0;                     // uploaded point vertices
  const SlotLayout& layout() const { return layout_; }

 private:
  BackendLimits limits_;
  SlotLayout layout_;
};

}  // namespace hv::render
