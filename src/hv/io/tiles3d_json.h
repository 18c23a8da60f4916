// JSON helpers shared by the 3D Tiles readers (tiles3d.cpp: tileset.json; pnts.cpp: the feature
// table): values shortened for messages, and arrays of finite numbers checked by count.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace hv::tiles3d_json {

// `v` is a finite number.
bool finiteNumber(const nlohmann::json& v);

// A JSON value, shortened for messages.
std::string shown(const nlohmann::json& v);

// `v` as exactly `n` finite numbers; otherwise an InputError naming `url`, `field` and `what`.
std::vector<double> numbers(const nlohmann::json& v, std::size_t n, const std::string& url, const std::string& field,
                            const std::string& what);

}  // namespace hv::tiles3d_json
