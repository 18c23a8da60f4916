#include "hv/io/web_geocentric.h"

#include "hv/util/diagnostics.h"

#include <cmath>

namespace hv {

using nlohmann::json;

json geocentricJson(const GeocentricFit& fit) {
  json coefficients = json::array();
  for (const glm::dvec3& c : fit.coefficients) coefficients.push_back({c.x, c.y, c.z});
  return {{"centre", {fit.centre.x, fit.centre.y, fit.centre.z}},
          {"scale", fit.scale},
          {"coefficients", coefficients},
          {"maxError", fit.maxError}};
}

namespace {
glm::dvec3 triple(const json& v, const std::string& where, const std::string& field) {
  if (!v.is_array() || v.size() != 3)
    throw InputError(where + ": " + field + ": expected 3 numbers, got " + v.dump().substr(0, 60));
  glm::dvec3 out;
  for (int k = 0; k < 3; ++k) {
    if (!v[std::size_t(k)].is_number() || !std::isfinite(v[std::size_t(k)].get<double>()))
      throw InputError(where + ": " + field + ": expected 3 finite numbers, got " + v.dump().substr(0, 60));
    out[k] = v[std::size_t(k)].get<double>();
  }
  return out;
}
}  // namespace

GeocentricFit geocentricFromJson(const json& j, const std::string& where) {
  if (!j.is_object()) throw InputError(where + ": geocentric: expected an object {centre, scale, coefficients}");
  GeocentricFit fit;
  fit.centre = triple(j.value("centre", json()), where, "geocentric.centre");
  const json s = j.value("scale", json());
  if (!s.is_number() || !(s.get<double>() > 0.0) || !std::isfinite(s.get<double>()))
    throw InputError(where + ": geocentric.scale: expected a number > 0, got " + s.dump());
  fit.scale = s.get<double>();
  const json c = j.value("coefficients", json());
  if (!c.is_array() || c.size() != 10)
    throw InputError(where + ": geocentric.coefficients: expected 10 triples of numbers");
  for (std::size_t k = 0; k < 10; ++k)
    fit.coefficients[k] = triple(c[k], where, "geocentric.coefficients[" + std::to_string(k) + "]");
  const json e = j.value("maxError", json(0.0));
  fit.maxError = e.is_number() ? e.get<double>() : 0.0;
  return fit;
}

}  // namespace hv
