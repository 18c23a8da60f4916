// JSON inputs as every reader of hv/io takes them (docs/formats.md, "Limits"): size-capped, from
// regular files only (hv/util/diagnostics.h), with the two ways a JSON writer silently disagrees
// with nlohmann made visible.
#pragma once

#include "hv/util/diagnostics.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace hv {

// Parses `text` (from `file`, for messages). Throws InputError naming the file when it is not JSON.
// - Python's json.dump writes NaN, Infinity and -Infinity as bare words, which JSON does not have:
//   they are read as the strings "NaN", "Infinity" and "-Infinity", so that the field reader names
//   the one item holding them (and leaves it out) instead of the whole file failing to parse.
// - A key repeated in one object is kept by nlohmann with its last value, silently: each is
//   reported in `diag` as a warning naming the object (by its "id" when it has one) and the key.
nlohmann::json parseJsonInput(const std::string& text, const std::string& file, Diagnostics& diag);

// readTextFile(path, kMaxJsonBytes, what) then parseJsonInput.
nlohmann::json readJsonInput(const std::string& path, const std::string& what, Diagnostics& diag);

// A GeoJSON FeatureCollection page, as a WFS GetFeature or an OGC API – Features `items` request
// answers it. Throws InputError naming `name` when `text` is not JSON or not a FeatureCollection
// with a "features" array. `next`: the href of its `links` entry with rel "next" (OGC API paging),
// or empty.
nlohmann::json parseFeatureCollection(const std::string& text, const std::string& name, std::string& next);

// True for the strings parseJsonInput turns the non-finite literals into.
bool isNonFiniteLiteral(const nlohmann::json& v);

// "unknown key 'distorsion' (did you mean 'distortion'?)", or without the hint when no known key
// is near; for each key of `object` that is not in `known`, in the object's order.
std::vector<std::string> unknownKeys(const nlohmann::json& object, const std::vector<std::string>& known);

}  // namespace hv
