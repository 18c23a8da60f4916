#include "hv/viewer/desktop/map_panel.h"

#include <imgui.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <iostream>
#include <utility>

namespace hv::viewer {

MapPanel::MapPanel(const Scene& scene, const std::vector<bool>& dated, std::shared_ptr<const Orthophoto> orthophoto)
    : map_(mapOverview(scene, dated)), orthophoto_(std::move(orthophoto)) {
  if (orthophoto_) orthophotoBox_ = orthophotoOnMap(map_, *orthophoto_, scene.origin);
}

MapPanel::Result MapPanel::draw(const Camera& view, int chosen) {
  Result result;
  if (!open_) return result;
  ImGui::SetNextWindowPos(ImVec2(380, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(340, 360), ImGuiCond_FirstUseEver);
  if (!ImGui::Begin("Map", &open_, ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse)) {
    ImGui::End();
    return result;
  }
  if (ImGui::SmallButton("Whole map")) zoom_ = MapZoom{};
  ImGui::SameLine();
  ImGui::TextDisabled("x%.1f  wheel: zoom, drag: pan", zoom_.zoom);
  const ImVec2 avail = ImGui::GetContentRegionAvail();
  const float w = std::max(64.0f, avail.x), h = std::max(64.0f, avail.y);
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  const bool released = ImGui::InvisibleButton("##map", ImVec2(w, h));  // pressed, then released over it
  // A drag pans, the wheel zooms about the pointer, a release that did not drag is a click. The pan
  // is the whole drag (from the press, through the release frame) applied to the zoom at the
  // press: slow frames that see several moves, or the release, at once lose none of it.
  const ImGuiIO& io = ImGui::GetIO();
  const glm::dvec2 mouse(io.MousePos.x - p0.x, io.MousePos.y - p0.y);
  if (ImGui::IsItemActivated()) panFrom_ = zoom_;
  if (ImGui::IsItemActive() || ImGui::IsItemDeactivated()) {
    const ImVec2 drag = ImGui::GetMouseDragDelta(ImGuiMouseButton_Left, 0.0f);
    zoom_ = panBy(map_.extent, int(w), int(h), panFrom_, {drag.x, drag.y});
  }
  if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenBlockedByActiveItem) && io.MouseWheel != 0.0f) {
    zoom_ = zoomAbout(map_.extent, int(w), int(h), zoom_, mouse, wheelZoomFactor(io.MouseWheel));
    panFrom_ = zoom_;  // a drag goes on from here
    ImGui::ResetMouseDragDelta(ImGuiMouseButton_Left);
  }
  const bool clicked = released && io.MouseDragMaxDistanceSqr[ImGuiMouseButton_Left] < 9.0f;
  const MapFrame frame = zoomedMap(map_.extent, int(w), int(h), zoom_);
  auto at = [&](const glm::dvec2& plane) {
    const glm::dvec2 px = frame.toPixel(plane);
    return ImVec2(p0.x + float(px.x), p0.y + float(px.y));
  };
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->PushClipRect(p0, ImVec2(p0.x + w, p0.y + h), true);
  dl->AddRectFilled(p0, ImVec2(p0.x + w, p0.y + h), IM_COL32(40, 42, 46, 255));
  // The hillshade, a grey texture over the height grid's box.
  if (!map_.shade.data.empty()) {
    if (!uploaded_) {
      Image8 rgba(map_.shade.width, map_.shade.height, 4);
      for (int y = 0; y < rgba.height; ++y)
        for (int x = 0; x < rgba.width; ++x) {
          const std::uint8_t g = map_.shade.at(x, y, 0);
          rgba.at(x, y, 0) = rgba.at(x, y, 1) = rgba.at(x, y, 2) = g;
          rgba.at(x, y, 3) = map_.shade.at(x, y, 1);
        }
      shade_.upload(rgba);
      uploaded_ = true;
    }
    const PlaneBox& b = map_.terrain.box;
    dl->AddImage(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(shade_.id())), at({b.lo.x, b.hi.y}),
                 at({b.hi.x, b.lo.y}));
  }
  // The orthophoto over it (uploaded at the first draw).
  if (orthophotoBox_) {
    if (!orthophotoTexture_.id()) {
      Image8 rgba(orthophoto_->width, orthophoto_->height, 4);
      rgba.data = orthophoto_->rgba;
      orthophotoTexture_.upload(rgba);
    }
    const PlaneBox& b = *orthophotoBox_;
    dl->AddImage(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(orthophotoTexture_.id())),
                 at({b.lo.x, b.hi.y}), at({b.hi.x, b.lo.y}));
  }
  // The footprints, filled, then their outlines.
  const auto& tri = map_.footprintTriangles;
  for (std::size_t i = 0; i + 2 < tri.size(); i += 3)
    dl->AddTriangleFilled(at(tri[i]), at(tri[i + 1]), at(tri[i + 2]), IM_COL32(150, 140, 130, 200));
  const auto& seg = map_.outlineSegments;
  for (std::size_t i = 0; i + 1 < seg.size(); i += 2)
    dl->AddLine(at(seg[i]), at(seg[i + 1]), IM_COL32(40, 30, 25, 255), 1.0f);
  // The photographs: a dot and a short line along the viewing direction.
  for (const MapDot& d : map_.dots) {
    const ImVec2 c = at(d.at);
    const ImU32 colour = d.dated ? IM_COL32(240, 160, 40, 255) : IM_COL32(120, 170, 230, 255);
    const glm::dvec2 dir = pixelDirection(d.direction);
    dl->AddLine(c, ImVec2(c.x + 10.0f * float(dir.x), c.y + 10.0f * float(dir.y)), colour, 1.5f);
    dl->AddCircleFilled(c, 3.5f, colour);
    if (d.photo == chosen) dl->AddCircle(c, 6.5f, IM_COL32(0, 230, 230, 255), 0, 1.5f);
  }
  // The view: a red triangle pointing along its heading.
  const MapView v = mapView(map_, view);
  const ImVec2 c = at(v.at);
  glm::dvec2 dir = pixelDirection(v.direction);
  if (dir == glm::dvec2(0.0)) dir = {0.0, -1.0};
  const glm::dvec2 side(-dir.y, dir.x);
  auto off = [&](double f, double s) {
    return ImVec2(c.x + float(f * dir.x + s * side.x), c.y + float(f * dir.y + s * side.y));
  };
  dl->AddTriangleFilled(off(11, 0), off(-5, 6), off(-5, -6), IM_COL32(230, 40, 40, 255));
  dl->PopClipRect();
  const std::array<double, 7> shown{p0.x, p0.y, w, h, frame.pixelsPerUnit, frame.offset.x, frame.offset.y};
  if (printDots_ && shown != printedAt_) {
    printedAt_ = shown;
    for (const MapDot& d : map_.dots)
      std::cout << "viewer: map: photograph " << d.photo << " at " << at(d.at).x << " " << at(d.at).y << "\n";
    std::cout << std::flush;
  }
  if (clicked) {
    const MapClick click = clickMap(map_, frame, mouse, 6.0);
    if (click.photo >= 0)
      result.photo = click.photo;
    else
      result.ground = click.ground;
  }
  ImGui::End();
  return result;
}

}  // namespace hv::viewer
