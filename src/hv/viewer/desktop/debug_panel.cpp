#include "hv/viewer/desktop/debug_panel.h"

#include <imgui.h>

#include <algorithm>

namespace hv::viewer {

bool drawDebugState(const render::Renderer& renderer, const Scene& scene, render::DebugSettings& debug) {
  bool changed = false;
  const render::RenderStats& st = renderer.stats();
  const bool chosen = debug.photo >= 0 && debug.photo < int(scene.photos.size());
  const char* id = chosen ? scene.photos[size_t(debug.photo)].camera.id.c_str() : "none";
  switch (debug.view) {
    case render::DebugView::Counts:
      ImGui::TextDisabled("black: none ... yellow: %d images", int(renderer.lastImageParams().size()));
      break;
    case render::DebugView::Weight:
      ImGui::TextDisabled("share of %s in each pixel: purple 0 ... yellow 1", id);
      if (chosen && st.debugImage < 0) {
        const auto& images = renderer.lastPlan().images;
        const bool selected = std::any_of(images.begin(), images.end(),
                                          [&](const ibr::SelectedImage& im) { return im.photo == debug.photo; });
        ImGui::TextDisabled(selected ? "(%s is waiting: decoding or its depth map)"
                                     : "(%s is not among this frame's K images)", id);
      }
      break;
    case render::DebugView::DepthMap:
      if (st.debugSlot < 0)
        ImGui::TextDisabled("%s: %s", id,
                            chosen ? photoStateName(renderer.photoState(debug.photo)) : "choose a photograph");
      else
        ImGui::TextDisabled("%s: yellow %.1f ... purple %.1f (depth), black: nothing", id, st.debugDepthNear,
                            st.debugDepthFar);
      break;
    case render::DebugView::None:
      break;
  }
  if (debug.frusta) ImGui::TextDisabled("frusta: yellow this frame's images, cyan the chosen photo");

  const auto& plan = renderer.lastPlan();
  const int ready = int(plan.images.size()) - st.imagesWaiting;
  const std::string progress =
      std::to_string(ready) + " / " + std::to_string(plan.images.size()) + " images in the frame";
  ImGui::ProgressBar(plan.images.empty() ? 1.0f : float(ready) / float(plan.images.size()), ImVec2(-1, 0),
                     progress.c_str());
  ImGui::Text("waiting: %d decoding, %d depth maps; %d resident of %d slots", st.decodesWaiting, st.depthMapsWaiting,
              st.residentImages, renderer.sliceCount());
  ImGui::Text("%d photographs decoded, %d depth maps rendered (%d this frame)", st.imagesLoaded,
              st.depthMapsRendered, st.depthMapsThisFrame);
  ImGui::Text("tile lists: mean %.1f, max %d images", st.meanTileList, st.maxTileList);
  if (st.streamingTerrain)
    ImGui::Text("terrain tiles: %d resident (%.1f of %.0f MiB), %d pending; view %d tiles, waiting for %d; %zu evicted",
                st.terrainTilesResident, double(st.terrainBytes) / (1 << 20), double(st.terrainBudgetBytes) / (1 << 20),
                st.terrainTilesPending, st.terrainViewTiles, st.terrainViewMissing, st.terrainEvictions);
  if (st.streamingBuildings)
    ImGui::Text("building tiles: %d resident (%zu buildings, %.1f MiB), %d pending; view %d tiles, waiting for %d%s; "
                "%zu evicted",
                st.buildingTilesResident, st.buildingsResident, double(st.buildingBytes) / (1 << 20),
                st.buildingTilesPending, st.buildingViewTiles, st.buildingViewMissing,
                st.buildingBudgetLimited ? " (some left out for the budget)" : "", st.buildingEvictions);
  if (ImGui::BeginTable("images", 5, ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg | ImGuiTableFlags_ScrollY,
                        ImVec2(0, 160))) {
    ImGui::TableSetupColumn("photo");
    ImGui::TableSetupColumn("slot");
    ImGui::TableSetupColumn("distance");
    ImGui::TableSetupColumn("weight");
    ImGui::TableSetupColumn("state");
    ImGui::TableHeadersRow();
    for (const auto& im : plan.images) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      // A click chooses the photograph for the debug views without moving the camera.
      if (ImGui::Selectable(scene.photos[size_t(im.photo)].camera.id.c_str(), debug.photo == im.photo,
                            ImGuiSelectableFlags_SpanAllColumns)) {
        debug.photo = im.photo;
        changed = true;
      }
      ImGui::TableNextColumn();
      const int slot = renderer.slotOf(im.photo);
      if (slot >= 0) ImGui::Text("%d", slot);
      else ImGui::TextDisabled("-");
      ImGui::TableNextColumn();
      ImGui::Text("%.1f", im.distance);
      ImGui::TableNextColumn();
      ImGui::Text("%.4f", im.weight);
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(photoStateName(renderer.photoState(im.photo)));
    }
    ImGui::EndTable();
  }
  return changed;
}

const char* photoStateName(render::PhotoState s) {
  switch (s) {
    case render::PhotoState::Absent: return "not resident";
    case render::PhotoState::Decoding: return "decoding";
    case render::PhotoState::DepthMapPending: return "depth map pending";
    case render::PhotoState::Ready: return "ready";
    case render::PhotoState::Broken: return "broken";
  }
  return "";
}

}  // namespace hv::viewer
