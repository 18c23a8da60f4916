#include "hv/render/settings_schema.h"

#include "hv/util/dates.h"

#include <nlohmann/json.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <type_traits>

namespace hv::render {

namespace {

constexpr std::size_t kMiB = std::size_t(1) << 20;

// A field's C++ value as a SettingValue and back (enums apart: they go through their spellings).
template <class T>
SettingValue toValue(const T& v) {
  if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, double> || std::is_same_v<T, glm::dvec3> ||
                std::is_same_v<T, std::vector<std::string>>)
    return v;
  else if constexpr (std::is_integral_v<T>)
    return std::int64_t(v);
  else if constexpr (std::is_same_v<T, std::vector<int>>)
    return std::vector<std::int64_t>(v.begin(), v.end());
  else
    static_assert(sizeof(T) == 0, "a settings field of a type the schema does not know");
}

template <class T>
void fromValue(const SettingValue& v, T& out) {
  if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, double> || std::is_same_v<T, glm::dvec3> ||
                std::is_same_v<T, std::vector<std::string>>)
    out = std::get<T>(v);
  else if constexpr (std::is_integral_v<T>)
    out = T(std::get<std::int64_t>(v));
  else if constexpr (std::is_same_v<T, std::vector<int>>) {
    const auto& items = std::get<std::vector<std::int64_t>>(v);
    out.assign(items.begin(), items.end());
  } else
    static_assert(sizeof(T) == 0, "a settings field of a type the schema does not know");
}

template <class T>
constexpr SettingType typeOf() {
  if constexpr (std::is_same_v<T, bool>) return SettingType::Bool;
  else if constexpr (std::is_integral_v<T>) return SettingType::Int;
  else if constexpr (std::is_same_v<T, double>) return SettingType::Double;
  else if constexpr (std::is_same_v<T, std::vector<int>>) return SettingType::IntList;
  else if constexpr (std::is_same_v<T, std::vector<std::string>>) return SettingType::TextList;
  else return SettingType::Colour;
}

// One table entry being declared: the chained calls fill in what is not the default.
struct Entry {
  Setting s;
  Entry& unit(std::string u) { s.unit = std::move(u); return *this; }
  Entry& range(double lo, double hi) { s.min = lo; s.max = hi; return slider(lo, hi); }
  Entry& above(double lo) { s.min = lo; s.minExclusive = true; return *this; }
  Entry& atLeast(double lo) { s.min = lo; return *this; }
  Entry& atMost(double hi) { s.max = hi; return *this; }
  Entry& slider(double lo, double hi, bool logarithmic = false) {
    s.sliderMin = lo;
    s.sliderMax = hi;
    s.logarithmic = logarithmic;
    return *this;
  }
  // "auto" stands for the field's value in a default RenderSettings (the renderer derives it).
  Entry& autoDefault() { s.autoValue = std::get<double>(s.get(RenderSettings{})); return *this; }
  Entry& reload() { s.apply = SettingApply::Reload; return *this; }
};

// `ref` is a generic lambda returning the field of a (const or mutable) RenderSettings.
template <class Ref>
Entry field(std::string name, std::string group, std::string help, Ref ref) {
  using T = std::decay_t<decltype(ref(std::declval<RenderSettings&>()))>;
  Entry e;
  e.s.name = std::move(name);
  e.s.group = std::move(group);
  e.s.help = std::move(help);
  e.s.type = typeOf<T>();
  e.s.get = [ref](const RenderSettings& s) { return toValue(ref(s)); };
  e.s.set = [ref](RenderSettings& s, const SettingValue& v) { fromValue(v, ref(s)); };
  return e;
}

// An enum field whose values, in declaration order, are spelt `spellings`.
template <class Ref>
Entry choice(std::string name, std::string group, std::string help, std::vector<std::string> spellings, Ref ref) {
  using E = std::decay_t<decltype(ref(std::declval<RenderSettings&>()))>;
  Entry e;
  e.s.name = std::move(name);
  e.s.group = std::move(group);
  e.s.help = std::move(help);
  e.s.type = SettingType::Enum;
  e.s.spellings = spellings;
  e.s.get = [ref, spellings](const RenderSettings& s) -> SettingValue { return spellings.at(size_t(ref(s))); };
  e.s.set = [ref, spellings](RenderSettings& s, const SettingValue& v) {
    for (size_t i = 0; i < spellings.size(); ++i)
      if (spellings[i] == std::get<std::string>(v)) ref(s) = E(i);
  };
  return e;
}

// A byte count shown in MiB.
template <class Ref>
Entry mebibytes(std::string name, std::string group, std::string help, Ref ref) {
  Entry e;
  e.s.name = std::move(name);
  e.s.group = std::move(group);
  e.s.help = std::move(help);
  e.s.type = SettingType::Int;
  e.s.get = [ref](const RenderSettings& s) -> SettingValue { return std::int64_t(ref(s) / kMiB); };
  e.s.set = [ref](RenderSettings& s, const SettingValue& v) { ref(s) = std::size_t(std::get<std::int64_t>(v)) * kMiB; };
  e.s.unit = "MiB";
  return e;
}

// One end of the time window (BlendSettings::window): `from` keeps the first day of the interval
// its date names, `to` the last (hv/util/dates.h); both open is no window at all.
Entry windowEnd(bool from) {
  Entry e;
  e.s.name = from ? "from" : "to";
  e.s.group = "Time window";
  e.s.help = from ? "only photographs dated on or after this date (a partial date such as 1905 is the interval "
                    "it names; dates match when the intervals overlap); empty: open"
                  : "only photographs dated on or before this date; empty: open";
  e.s.type = SettingType::Date;
  e.s.get = [from](const RenderSettings& s) -> SettingValue {
    const DateInterval open;
    if (!s.blend.window) return std::string();
    const std::int64_t day = from ? s.blend.window->first : s.blend.window->last;
    return day == (from ? open.first : open.last) ? std::string() : formatDay(day);
  };
  e.s.set = [from](RenderSettings& s, const SettingValue& v) {
    const std::string& text = std::get<std::string>(v);
    DateInterval w = s.blend.window.value_or(DateInterval{});
    const DateInterval open;
    if (text.empty()) (from ? w.first : w.last) = from ? open.first : open.last;
    else (from ? w.first : w.last) = from ? parseDate(text)->first : parseDate(text)->last;
    if (w.first > w.last)
      throw std::invalid_argument("--from " + formatDay(w.first) + " is after --to " + formatDay(w.last) +
                                  ": the time window is empty");
    if (w == open) s.blend.window.reset();
    else s.blend.window = w;
  };
  return e;
}

std::vector<Setting> makeSchema() {
  const std::string blend = "Blending", untextured = "Untextured surfaces and sky", time = "Time window",
                    depth = "Depth maps", layers = "Geometry", points = "Points", debug = "Debug",
                    resources = "Resources", traffic = "Traffic";
  std::vector<Entry> t;
  // Brédif 2013 eq. 1-2: the K nearest cameras, weights f(d_i) - f(d_K+1), f(d) = 1/(sigma^2 + d^2).
  t.push_back(field("k", blend, "photographs blended per pixel (the K nearest cameras that see it; with selection "
                    "global, the K nearest to the view)",
                    [](auto& s) -> auto& { return s.blend.k; }).atLeast(1).slider(1, 32));
  // Buehler et al. 2001 (ULR): the best k per pixel, with Brédif 2013's weights.
  t.push_back(choice("selection", blend, "region: every part of the view is textured by its own nearest photographs "
                     "(per pixel, the K nearest of the frame's candidates that pass the tests, weighted against the "
                     "K+1-th there); global: the papers' K nearest to the view for the whole frame (default: on "
                     "street views it is still 0.06 dB better, docs/evaluation.md)",
                     {"region", "global"}, [](auto& s) -> auto& { return s.blend.selection; }));
  t.push_back(field("candidates", blend, "selection region: photographs a frame may make resident and pass to the "
                    "shader (also capped by the image slots); --k keeps its meaning, the most images blended at one "
                    "pixel, so K = 1 from a photograph's own camera reproduces it",
                    [](auto& s) -> auto& { return s.blend.candidates; }).atLeast(1).slider(1, 128));
  t.push_back(field("sigma", blend, "sigma of the weight f(d) = 1/(sigma^2 + d^2); auto: the median spacing of the "
                    "camera centres", [](auto& s) -> auto& { return s.blend.sigma; })
                  .unit("scene units").above(0).atMost(1e7).slider(0.01, 100, true).autoDefault());
  // Buehler et al. 2001's penalties, our formulation (docs/design.md, "Weights that know geometry").
  t.push_back(choice("weights", blend, "distance: the papers' weights by camera-centre distance; geometry: per pixel "
                     "the best K by the angle between the photograph's and the view's rays and the photograph's "
                     "resolution on the surface (grazing incidence included), weights vanishing as an image leaves "
                     "the best K (candidates: those of the selection; global, the --candidates nearest)",
                     {"distance", "geometry"}, [](auto& s) -> auto& { return s.blend.weighting; }));
  t.push_back(field("resolution-weight", blend, "weights geometry: radians of penalty per unit of ln(photograph texel "
                    "footprint / view pixel footprint) where the photograph is the blurrier",
                    [](auto& s) -> auto& { return s.blend.resolutionWeight; })
                  .unit("rad").atLeast(0).atMost(100).slider(0, 4));
  t.push_back(field("penalty-epsilon", blend, "weights geometry: f(p) = 1/(epsilon^2 + p^2) of the penalty p",
                    [](auto& s) -> auto& { return s.blend.penaltyEpsilon; })
                  .unit("rad").above(0).atMost(10).slider(0.001, 1, true));
  t.push_back(field("geometry-k", blend, "weights geometry: photographs blended per pixel, the best by penalty (at "
                    "most --k, which keeps its meaning; SIBR's ULR blends 4); fewer is faster: the shader visits the "
                    "candidates best first and stops at the K+1-th that passes; 0: --k",
                    [](auto& s) -> auto& { return s.blend.geometryK; }).atLeast(0).atMost(16).slider(0, 16));
  t.push_back(field("feather", blend, "weights fall smoothly to 0 over this many photograph pixels toward each "
                    "photograph's border, lens domain edge and mask edges; 0: hard edges (the papers')",
                    [](auto& s) -> auto& { return s.blend.featherPx; })
                  .unit("px").atLeast(0).atMost(1e4).slider(0, 256));
  t.push_back(field("consensus", blend, "transient filter: where the photographs at a pixel disagree, those far from "
                    "their common colour lose their weight (a Gaussian of this spread, RGB in 0-1, around the mode of "
                    "their colours); 0: off (the papers')",
                    [](auto& s) -> auto& { return s.blend.consensus; })
                  .atLeast(0).atMost(1).slider(0, 0.5));
  t.push_back(field("mipmaps", blend, "sample the photographs with mipmaps, the level from the projected footprint "
                    "through the lens distortion (off: level 0, the papers')",
                    [](auto& s) -> auto& { return s.blend.mipmaps; }));
  t.push_back(field("anisotropy", blend, "mipmaps: the most anisotropic filtering (where the context has "
                    "EXT_texture_filter_anisotropic); 1: none (the default: software rasterisers filter every anisotropic "
                    "sample in full)",
                    [](auto& s) -> auto& { return s.blend.anisotropy; })
                  .atLeast(1).atMost(64).slider(1, 16));
  t.push_back(choice("blend-method", blend, "blend the K photographs, or per pixel the nearest that passes the tests",
                     {"blend", "nearest"}, [](auto& s) -> auto& { return s.blend.method; }));
  t.push_back(field("occlusion", blend, "the depth-map (shadow) test: a photograph does not texture what it cannot see",
                    [](auto& s) -> auto& { return s.blend.occlusion; }));
  t.push_back(field("masks", blend, "apply the photographs' masks (off: they are decoded again without)",
                    [](auto& s) -> auto& { return s.blend.masks; }));
  t.push_back(field("colour-correction", blend, "apply each photograph's colour correction (gain and offset per "
                    "channel) from the file scene.json names (\"colour\", written by histoview harmonize); a "
                    "scene without one is unchanged", [](auto& s) -> auto& { return s.blend.colourCorrection; }));
  t.push_back(field("frustum-filter", blend, "only photographs that see part of the view frustum are candidates",
                    [](auto& s) -> auto& { return s.blend.frustumFilter; }));
  t.push_back(field("exclude", blend, "photograph ids left out (e.g. leave-one-out)",
                    [](auto& s) -> auto& { return s.blend.exclude; }));
  t.push_back(field("background", blend, "colour where no photograph contributes: of surfaces when shading is off, "
                    "of the sky when sky is off (on the command line, giving it turns the sky off)",
                    [](auto& s) -> auto& { return s.background; }));
  t.push_back(field("background-distance", blend, "where no geometry is seen, project the photographs onto a "
                    "sphere of this radius around the view (iTowns' backgroundDistance); 0: never; auto: only in "
                    "a scene without geometry, radius 100", [](auto& s) -> auto& { return s.backgroundSphere; })
                  .unit("scene units").atLeast(0).slider(1, 10000, true).autoDefault());

  // Where no photograph contributes (render/untextured.h); never coverage (output alpha 0).
  t.push_back(field("shading", untextured, "surfaces no photograph textures are drawn shaded (a neutral material "
                    "under sky, ground and sun light), not in the background colour",
                    [](auto& s) -> auto& { return s.untextured.shading; }));
  t.push_back(field("sky", untextured, "pixels that see no geometry show a sky gradient, horizon to zenith, not the "
                    "background colour", [](auto& s) -> auto& { return s.untextured.sky; }));
  t.push_back(field("sun-azimuth", untextured, "shading: the sun's direction, clockwise from north (the scene's y "
                    "axis when up is z) towards east", [](auto& s) -> auto& { return s.untextured.sunAzimuthDeg; })
                  .unit("degrees").range(0, 360));
  t.push_back(field("sun-elevation", untextured, "shading: the sun's height above the horizon",
                    [](auto& s) -> auto& { return s.untextured.sunElevationDeg; })
                  .unit("degrees").range(0, 90));
  t.push_back(field(
      "orthophoto", untextured,
      "untextured terrain shows the scene's orthophoto (scene.json "
      "\"orthophoto\") where it covers it, as it is, instead of the shading",
      [](auto& s) -> auto& { return s.untextured.orthophoto; }));

  t.push_back(windowEnd(true));
  t.push_back(windowEnd(false));
  t.push_back(field("dated-only", time, "leave out undated photographs (kept by default)",
                    [](auto& s) -> auto& { return s.blend.datedOnly; }));

  t.push_back(field("depth-size", depth, "depth-map resolution (square)", [](auto& s) -> auto& { return s.depthSize; })
                  .unit("px").range(16, 16384).slider(256, 4096, true).reload());
  t.push_back(field("depth-maps-per-frame", depth, "progressive frames: depth maps rendered per frame, nearest "
                    "camera first (Dmax)", [](auto& s) -> auto& { return s.depthMapsPerFrame; })
                  .atLeast(1).slider(1, 64));
  t.push_back(field("depth-budget-ms", depth, "progressive frames: render depth maps until this time is spent (at "
                    "least one); 0: off", [](auto& s) -> auto& { return s.depthBudgetMs; })
                  .unit("ms").atLeast(0).slider(0, 200));
  t.push_back(field("depth-bias", depth, "absolute part of the slope-scaled shadow bias; auto: from the scene's "
                    "extent", [](auto& s) -> auto& { return s.depthBiasAbsolute; })
                  .unit("scene units").atLeast(0).slider(0.001, 10, true).autoDefault());
  t.push_back(field("depth-bias-texels", depth, "plus this many depth-map texel footprints (ibr::shadowBias)",
                    [](auto& s) -> auto& { return s.depthBiasTexels; }).unit("texels").atLeast(0).slider(0, 8));

  t.push_back(field("terrain", layers, "draw the terrain (in the view and the depth maps)",
                    [](auto& s) -> auto& { return s.layers.terrain; }));
  t.push_back(field("buildings", layers, "draw the LOD1 buildings", [](auto& s) -> auto& { return s.layers.buildings; }));
  t.push_back(field("mesh", layers, "draw the scene's mesh", [](auto& s) -> auto& { return s.layers.mesh; }));
  t.push_back(field("distortion", layers, "correct the photographs' lens distortion (off: projected as pinholes, "
                    "to see what the correction does)", [](auto& s) -> auto& { return s.layers.lensDistortion; }));

  // Devaux & Brédif 2016, de Castro & Brédif 2022 §2.4: textured point sprites, filtered.
  t.push_back(field("points", points, "draw the scene's point cloud as textured sprites",
                    [](auto& s) -> auto& { return s.points.enabled; }));
  t.push_back(field("point-budget", points, "points drawn per frame (and per depth map)",
                    [](auto& s) -> auto& { return s.points.budget; }).atLeast(1).slider(10000, 20000000, true));
  t.push_back(field("point-radius", points, "sprite radius; auto: point-radius-scale x each chunk's point spacing",
                    [](auto& s) -> auto& { return s.points.radius; })
                  .unit("scene units").above(0).slider(0.01, 5, true).autoDefault());
  t.push_back(field("point-radius-scale", points, "auto sprite radius, times each chunk's point spacing",
                    [](auto& s) -> auto& { return s.points.radiusScale; }).above(0).slider(0.1, 4));
  t.push_back(field("max-point-size", points, "largest sprite on screen (also capped by ALIASED_POINT_SIZE_RANGE)",
                    [](auto& s) -> auto& { return s.points.maxPointSizePx; })
                  .unit("px").atLeast(1).slider(1, 256, true).reload());
  t.push_back(choice("sprite-form", points, "nprime: one vec3 varying (2022); mat3: a mat3 varying per image (2016; K "
                     "capped by the varyings)", {"nprime", "mat3"}, [](auto& s) -> auto& { return s.points.form; })
                  .reload());
  t.push_back(choice("point-filter", points, "which points the photographs texture; auto: class when the cloud is "
                     "classified, else epsilon", {"auto", "class", "epsilon", "none"},
                     [](auto& s) -> auto& { return s.points.filter; }));
  t.push_back(field("kept-classes", points, "class filter: the non-transient ASPRS classes, textured",
                    [](auto& s) -> auto& { return s.points.keptClasses; }).range(0, 255));
  t.push_back(field("points-in-depth-maps", points, "class filter: the kept points occlude in the depth maps (off: "
                    "the model only)", [](auto& s) -> auto& { return s.points.keptInDepthMaps; }));
  t.push_back(field("hide-transient", points, "do not draw transient points (default: in their own colour)",
                    [](auto& s) -> auto& { return s.points.hideTransient; }));
  t.push_back(field("epsilon", points, "epsilon filter: a photograph textures a point within this of the model's "
                    "depth; auto: 2e-3 of the scene's extent", [](auto& s) -> auto& { return s.points.epsilon; })
                  .unit("scene units").atLeast(0).slider(0.001, 5, true).autoDefault());
  t.push_back(field("mesh-offset", points, "hybrid: the mesh counts as pushed back by this along its normal behind "
                    "the points; auto: 6e-4 of the scene's extent", [](auto& s) -> auto& { return s.points.meshOffset; })
                  .unit("scene units").atLeast(0).slider(0.001, 5, true).autoDefault());
  t.push_back(choice("point-color", points, "colour of untextured points", {"auto", "rgb", "intensity", "class"},
                     [](auto& s) -> auto& { return s.points.color; }).reload());
  t.push_back(field("eye-dome", points, "eye-dome lighting on untextured points",
                    [](auto& s) -> auto& { return s.points.eyeDome; }));
  t.push_back(field("eye-dome-strength", points, "eye-dome lighting strength",
                    [](auto& s) -> auto& { return s.points.eyeDomeStrength; }).atLeast(0).slider(0, 2));
  t.push_back(field("eye-dome-radius", points, "eye-dome lighting neighbour distance",
                    [](auto& s) -> auto& { return s.points.eyeDomeRadiusPx; }).unit("px").above(0).slider(0.5, 5));

  t.push_back(field("traffic", traffic, "draw the vehicles of scene.json's traffic (a simulator's trajectories) "
                    "at --time, lifted onto the terrain, hidden by the geometry in front of them",
                    [](auto& s) -> auto& { return s.traffic.enabled; }));
  t.push_back(field("time", traffic, "the traffic's simulation clock: a vehicle is shown between its first and last "
                    "sample", [](auto& s) -> auto& { return s.traffic.time; })
                  .unit("s").atLeast(0).slider(0, 3600));

  t.push_back(choice("debug-view", debug, "the picture, or a debug view: contributing images per pixel, the chosen "
                     "photograph's weight or its depth map (docs/viewer.md)", {"picture", "count", "weight", "depth"},
                     [](auto& s) -> auto& { return s.debug.view; }));
  t.push_back(field("frusta", debug, "draw the photographs' frusta over the picture (the frame's images yellow, the "
                    "chosen photograph cyan)", [](auto& s) -> auto& { return s.debug.frusta; }));
  t.push_back(field("frustum-depth", debug, "frustum length along the camera axis; auto: the camera spacing",
                    [](auto& s) -> auto& { return s.debug.frustumDepth; })
                  .unit("scene units").above(0).slider(0.1, 100, true).autoDefault());

  t.push_back(choice("binding", resources, "array: texture arrays; naive: the baseline, a sampler2D per image and "
                     "per depth map", {"array", "naive"}, [](auto& s) -> auto& { return s.binding; }).reload());
  t.push_back(field("tile-culling", resources, "per-tile image lists: each pixel loops over the images that may "
                    "cover its tile", [](auto& s) -> auto& { return s.tileCulling; }));
  t.push_back(field("geometry-culling", resources, "the view and each depth map draw only the geometry tiles "
                    "their frustum may see (off: every tile; the same pixels)",
                    [](auto& s) -> auto& { return s.geometryCulling; }));
  t.push_back(field("tile-size", resources, "tile side, in view-depth texels", [](auto& s) -> auto& { return s.tileSize; })
                  .unit("px").range(1, 256).slider(4, 64, true));
  t.push_back(field("max-slice-size", resources, "largest photograph side in the texture array (larger ones are "
                    "scaled down)", [](auto& s) -> auto& { return s.maxSliceSize; })
                  .unit("px").range(16, 16384).slider(256, 8192, true).reload());
  t.push_back(field("max-slices", resources, "photograph slots (also capped by MAX_ARRAY_TEXTURE_LAYERS and memory)",
                    [](auto& s) -> auto& { return s.maxSlices; }).range(1, 65536).slider(1, 2048, true).reload());
  t.push_back(mebibytes("memory-budget", resources, "GPU memory for the photographs and their depth maps",
                        [](auto& s) -> auto& { return s.memoryBudgetBytes; }).atLeast(1).slider(64, 8192, true).reload());
  t.push_back(field("decode-threads", resources, "threads decoding photographs; 0: on the render thread",
                    [](auto& s) -> auto& { return s.decodeThreads; }).range(0, 64).slider(0, 16).reload());
  t.push_back(mebibytes("decode-memory", resources, "memory of decodes in flight and slices not yet uploaded",
                        [](auto& s) -> auto& { return s.decodeMemoryBytes; }).atLeast(1).slider(16, 4096, true).reload());

  t.push_back(field("geometry-threads", resources, "threads reading and meshing streamed terrain tiles; 0: on the "
                    "render thread", [](auto& s) -> auto& { return s.geometryThreads; }).range(0, 64).slider(0, 16).reload());
  t.push_back(mebibytes("geometry-memory", resources, "memory of the streamed terrain tiles (GPU meshes and their "
                        "samples); the least recently used are evicted",
                        [](auto& s) -> auto& { return s.geometryMemoryBytes; }).atLeast(1).slider(16, 4096, true).reload());
  t.push_back(field("geometry-tolerance", resources, "screen-space error a streamed terrain tile may have in the view "
                    "and in each depth map", [](auto& s) -> auto& { return s.geometryTolerancePx; })
                  .unit("px").above(0).slider(0.25, 32, true));
  t.push_back(field("building-min-pixels", resources, "streamed building tiles whose box is thinner than this in "
                    "the view are not drawn there (depth maps keep their reach); 0: every tile it may see",
                    [](auto& s) -> auto& { return s.buildingMinPixels; }).unit("px").atLeast(0).slider(0, 32));

  std::vector<Setting> out;
  for (Entry& e : t) out.push_back(std::move(e.s));
  return out;
}

// The shortest text that reads back as the same double.
std::string formatDouble(double v) {
  char buf[32];
  // Whole numbers as such ("10", not "1e+01", which %g prefers at precision 1).
  if (v == std::trunc(v) && std::fabs(v) < 1e15) {
    std::snprintf(buf, sizeof buf, "%.0f", v);
    return buf;
  }
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

std::string formatNumber(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return formatDouble(v);
}

std::string trimmed(const std::string& text) {
  const size_t b = text.find_first_not_of(" \t"), e = text.find_last_not_of(" \t");
  return b == std::string::npos ? std::string() : text.substr(b, e - b + 1);
}

// "2, 6,9" -> {"2", "6", "9"} (spaces around items dropped, as the command line's --background
// "0, 0, 0" always allowed); "" -> {}.
std::vector<std::string> splitCommas(const std::string& text) {
  std::vector<std::string> items;
  if (trimmed(text).empty()) return items;
  std::string item;
  std::istringstream in(text);
  while (std::getline(in, item, ',')) items.push_back(trimmed(item));
  if (text.back() == ',') items.push_back("");
  return items;
}

std::string join(const std::vector<std::string>& items, const char* sep) {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) out += (i ? sep : "") + items[i];
  return out;
}

std::optional<std::int64_t> readInt(const std::string& spaced) {
  const std::string text = trimmed(spaced);
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  if (*end != '\0' || errno == ERANGE) return std::nullopt;
  return std::int64_t(v);
}

std::optional<double> readDouble(const std::string& spaced) {
  const std::string text = trimmed(spaced);
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (*end != '\0' || !std::isfinite(v)) return std::nullopt;
  return v;
}

bool inRange(const Setting& s, double v) {
  return (s.minExclusive ? v > s.min : v >= s.min) && v <= s.max;
}

// "a number > 0", "a whole number in 16-16384".
std::string rangeText(const Setting& s, const char* what) {
  std::string out = what;
  if (std::isfinite(s.min) && std::isfinite(s.max)) return out + " in " + formatNumber(s.min) + "-" + formatNumber(s.max);
  if (std::isfinite(s.min)) out += std::string(s.minExclusive ? " > " : " >= ") + formatNumber(s.min);
  if (std::isfinite(s.max)) out += " <= " + formatNumber(s.max);
  return out;
}

}  // namespace

const std::vector<Setting>& settingsSchema() {
  static const std::vector<Setting> schema = makeSchema();
  return schema;
}

std::vector<std::string> settingGroups() {
  std::vector<std::string> groups;
  for (const Setting& s : settingsSchema())
    if (groups.empty() || groups.back() != s.group) groups.push_back(s.group);
  return groups;
}

const Setting* findSetting(std::string_view name) {
  for (const Setting& s : settingsSchema())
    if (s.name == name) return &s;
  return nullptr;
}

const Setting& setting(std::string_view name) {
  if (const Setting* s = findSetting(name)) return *s;
  std::vector<std::string> names;
  for (const Setting& s : settingsSchema()) names.push_back(s.name);
  throw std::invalid_argument("unknown setting '" + std::string(name) + "'; the settings are " + join(names, ", "));
}

const char* typeName(SettingType type) {
  switch (type) {
    case SettingType::Bool: return "bool";
    case SettingType::Int: return "int";
    case SettingType::Double: return "double";
    case SettingType::Enum: return "enum";
    case SettingType::IntList: return "int-list";
    case SettingType::TextList: return "text-list";
    case SettingType::Colour: return "colour";
    case SettingType::Date: return "date";
  }
  return "";
}

std::string expectedText(const Setting& s) {
  switch (s.type) {
    case SettingType::Bool: return "true or false";
    case SettingType::Int: return rangeText(s, "a whole number");
    case SettingType::Double: return rangeText(s, "a number") + (s.autoValue ? ", or auto" : "");
    case SettingType::Enum: return "one of " + join(s.spellings, ", ");
    case SettingType::IntList: return rangeText(s, "comma-separated whole numbers");
    case SettingType::TextList:
      return s.spellings.empty() ? "comma-separated names" : "comma-separated names among " + join(s.spellings, ", ");
    case SettingType::Colour: return "R,G,B with components in 0-255";
    case SettingType::Date: return "an ISO 8601 date (YYYY, YYYY-MM, YYYY-MM-DD or YYYY-MM-DDThh:mm[:ss]) or nothing";
  }
  return "";
}

SettingValue parseSettingValue(const Setting& s, const std::string& text) {
  auto fail = [&]() -> std::invalid_argument {
    return std::invalid_argument("--" + s.name + ": expected " + expectedText(s) + ", got '" + text + "'");
  };
  switch (s.type) {
    case SettingType::Bool:
      if (text == "true" || text == "on" || text == "yes" || text == "1") return true;
      if (text == "false" || text == "off" || text == "no" || text == "0") return false;
      throw fail();
    case SettingType::Int: {
      const auto v = readInt(text);
      if (!v || !inRange(s, double(*v))) throw fail();
      return *v;
    }
    case SettingType::Double: {
      if (s.autoValue && text == "auto") return *s.autoValue;
      const auto v = readDouble(text);
      if (!v || !inRange(s, *v)) throw fail();
      return *v;
    }
    case SettingType::Enum:
      for (const std::string& spelling : s.spellings)
        if (text == spelling) return text;
      throw fail();
    case SettingType::IntList: {
      std::vector<std::int64_t> items;
      for (const std::string& item : splitCommas(text)) {
        const auto v = readInt(item);
        if (!v || !inRange(s, double(*v))) throw fail();
        items.push_back(*v);
      }
      return items;
    }
    case SettingType::TextList: {
      std::vector<std::string> items = splitCommas(text);
      for (const std::string& item : items) {
        bool allowed = !item.empty() && s.spellings.empty();
        for (const std::string& spelling : s.spellings) allowed |= item == spelling;
        if (!allowed) throw fail();
      }
      return items;
    }
    case SettingType::Colour: {
      const std::vector<std::string> parts = splitCommas(text);
      if (parts.size() != 3) throw fail();
      glm::dvec3 c;
      for (int i = 0; i < 3; ++i) {
        const auto v = readDouble(parts[size_t(i)]);
        if (!v || *v < 0.0 || *v > 255.0) throw fail();
        c[i] = *v / 255.0;
      }
      return c;
    }
    case SettingType::Date:
      if (!text.empty() && !parseDate(text)) throw fail();
      return text;
  }
  throw fail();
}

std::string settingValueText(const Setting& s, const SettingValue& value) {
  switch (s.type) {
    case SettingType::Bool: return std::get<bool>(value) ? "true" : "false";
    case SettingType::Int: return std::to_string(std::get<std::int64_t>(value));
    case SettingType::Double: {
      const double v = std::get<double>(value);
      return s.autoValue && v == *s.autoValue ? "auto" : formatDouble(v);
    }
    case SettingType::Enum:
    case SettingType::Date: return std::get<std::string>(value);
    case SettingType::IntList: {
      std::vector<std::string> items;
      for (std::int64_t v : std::get<std::vector<std::int64_t>>(value)) items.push_back(std::to_string(v));
      return join(items, ",");
    }
    case SettingType::TextList: return join(std::get<std::vector<std::string>>(value), ",");
    case SettingType::Colour: {
      // Components in 0-255, rounded to 1e-6 so that a whole number written reads back whole.
      const glm::dvec3 c = std::get<glm::dvec3>(value);
      std::vector<std::string> parts;
      for (int i = 0; i < 3; ++i) parts.push_back(formatDouble(std::round(c[i] * 255.0 * 1e6) / 1e6));
      return join(parts, ",");
    }
  }
  return "";
}

void setFromText(RenderSettings& settings, std::string_view name, const std::string& text) {
  const Setting& s = setting(name);
  s.set(settings, parseSettingValue(s, text));
}

std::string toText(const RenderSettings& settings, std::string_view name) {
  const Setting& s = setting(name);
  return settingValueText(s, s.get(settings));
}

std::string defaultText(const Setting& s) { return settingValueText(s, s.get(RenderSettings{})); }

std::string settingsJson(const RenderSettings& current) {
  using json = nlohmann::json;
  json out = json::array();
  auto bound = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
  for (const Setting& s : settingsSchema())
    out.push_back({{"name", s.name},
                   {"type", typeName(s.type)},
                   {"group", s.group},
                   {"help", s.help},
                   {"unit", s.unit},
                   {"live", s.apply == SettingApply::Live},
                   {"min", bound(s.min)},
                   {"max", bound(s.max)},
                   {"minExclusive", s.minExclusive},
                   {"sliderMin", s.sliderMin},
                   {"sliderMax", s.sliderMax},
                   {"logarithmic", s.logarithmic},
                   {"auto", s.autoValue.has_value()},
                   {"spellings", s.spellings},
                   {"expected", expectedText(s)},
                   {"default", defaultText(s)},
                   {"value", settingValueText(s, s.get(current))}});
  return out.dump();
}

std::string settingsMarkdown() {
  std::ostringstream md;
  bool first = true;
  for (const std::string& group : settingGroups()) {
    md << (first ? "" : "\n") << "**" << group << "**\n\n";
    first = false;
    md << "| option | value | default | applies | what |\n|---|---|---|---|---|\n";
    for (const Setting& s : settingsSchema()) {
      if (s.group != group) continue;
      const std::string option = s.type == SettingType::Bool ? "`--[no-]" + s.name + "`" : "`--" + s.name + "`";
      std::string value = s.type == SettingType::Bool ? "flag" : expectedText(s);
      if (!s.unit.empty()) value += " (" + s.unit + ")";
      const std::string def = defaultText(s);
      md << "| " << option << " | " << value << " | " << (def.empty() ? "" : "`" + def + "`") << " | "
         << (s.apply == SettingApply::Live ? "live" : "new renderer") << " | " << s.help << " |\n";
    }
  }
  return md.str();
}

}  // namespace hv::render
