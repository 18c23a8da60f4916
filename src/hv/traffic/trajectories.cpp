#include "hv/traffic/trajectories.h"

#include "hv/util/diagnostics.h"
#include "hv/util/text.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>

namespace hv {
namespace {

constexpr std::size_t kMaxRows = 50000000;
constexpr double kPi = 3.14159265358979323846;

}  // namespace

VehicleSize vehicleSizeOf(const std::string& type, bool* known) {
  const std::string t = asciiLower(type);
  // SUMO's defaults per vehicle class (sumo.dlr.de, "Vehicle Type Parameter Defaults"), rounded.
  struct Entry {
    const char* key;
    VehicleSize size;
  };
  static const Entry kTable[] = {
      {"bus", {12.0, 2.5, 3.4}},      {"coach", {14.0, 2.6, 4.0}},          {"trailer", {16.5, 2.55, 4.0}},
      {"truck", {7.1, 2.4, 2.4}},     {"delivery", {6.5, 2.16, 2.86}},      {"motorcycle", {2.2, 0.9, 1.5}},
      {"moped", {2.1, 0.8, 1.7}},     {"bicycle", {1.6, 0.65, 1.7}},        {"tram", {22.0, 2.4, 3.2}},
      {"passenger", {5.0, 1.8, 1.5}}, {"default_vehtype", {5.0, 1.8, 1.5}}, {"car", {4.5, 1.8, 1.5}},
  };
  for (const Entry& e : kTable)
    if (t.find(e.key) != std::string::npos) {
      if (known) *known = true;
      return e.size;
    }
  if (known) *known = t.empty();
  return VehicleSize{};
}

std::size_t Trajectories::samples() const {
  std::size_t n = 0;
  for (const Trajectory& v : vehicles) n += v.samples.size();
  return n;
}

void TrajectoryBuilder::add(const std::string& id, const std::string& type, const TrajectorySample& sample) {
  auto it =
      std::lower_bound(index_.begin(), index_.end(), id,
                       [](const std::pair<std::string, std::size_t>& a, const std::string& b) { return a.first < b; });
  if (it == index_.end() || it->first != id) {
    it = index_.insert(it, {id, vehicles_.size()});
    Trajectory v;
    v.id = id;
    v.type = type;
    vehicles_.push_back(std::move(v));
  }
  vehicles_[it->second].samples.push_back(sample);
  ++rows_;
}

Trajectories TrajectoryBuilder::finish(const std::string& source, Diagnostics& diag) {
  Trajectories out;
  std::map<std::string, std::size_t> unknown;
  bool any = false;
  for (Trajectory& v : vehicles_) {
    std::stable_sort(v.samples.begin(), v.samples.end(),
                     [](const TrajectorySample& a, const TrajectorySample& b) { return a.t < b.t; });
    // A repeated time keeps its last row.
    std::vector<TrajectorySample> kept;
    for (const TrajectorySample& s : v.samples) {
      if (!kept.empty() && kept.back().t == s.t)
        kept.back() = s;
      else
        kept.push_back(s);
    }
    v.samples = std::move(kept);
    bool known = true;
    v.size = vehicleSizeOf(v.type, &known);
    if (!known) ++unknown[v.type];
    if (!any) {
      out.tBegin = v.samples.front().t;
      out.tEnd = v.samples.back().t;
      any = true;
    }
    out.tBegin = std::min(out.tBegin, v.samples.front().t);
    out.tEnd = std::max(out.tEnd, v.samples.back().t);
  }
  for (const auto& [type, count] : unknown)
    diag.warn(inputMessage(source, "type",
                           "unknown vehicle type '" + shownText(type) + "' (" + std::to_string(count) +
                               " vehicles): drawn as the default car, 4.5 x 1.8 x 1.5 m"));
  out.vehicles = std::move(vehicles_);
  vehicles_.clear();
  index_.clear();
  rows_ = 0;
  return out;
}

Trajectories parseTrajectoriesCsv(std::string_view text, const std::string& source, Diagnostics& diag) {
  if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // a UTF-8 BOM
  std::map<std::string, std::size_t> column;
  std::size_t width = 0;
  int lineNo = 0;
  std::size_t pos = 0;
  TrajectoryBuilder builder;
  std::vector<std::string_view> fields;
  while (pos <= text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = trimField(text.substr(pos, end - pos));
    pos = end + 1;
    ++lineNo;
    if (line.empty() || line.front() == '#') continue;
    fields.clear();
    std::size_t start = 0;
    for (std::size_t i = 0; i <= line.size(); ++i)
      if (i == line.size() || line[i] == ',') {
        fields.push_back(trimField(line.substr(start, i - start)));
        start = i + 1;
      }
    const std::string where = source + ": line " + std::to_string(lineNo);
    if (column.empty()) {  // the header
      for (std::size_t i = 0; i < fields.size(); ++i) column.emplace(asciiLower(fields[i]), i);
      for (const char* need : {"t", "id", "x", "y", "angle"})
        if (!column.count(need))
          throw InputError(where + ": the header has no column '" + need +
                           "' (expected a header naming t,id,x,y,angle,type: time in seconds, the vehicle's id, "
                           "its centre x, y, its heading in degrees clockwise from north; got '" +
                           shownText(line) + "')");
      width = fields.size();
      continue;
    }
    if (fields.size() != width)
      throw InputError(where + ": " + std::to_string(fields.size()) + " fields where the header has " +
                       std::to_string(width));
    if (builder.rows() >= kMaxRows) throw InputError(source + ": more than " + std::to_string(kMaxRows) + " rows");
    auto number = [&](const char* name) {
      const std::string_view f = fields[column.at(name)];
      const std::string copy(f);  // strtod: the browser build's library has no floating-point from_chars
      char* endp = nullptr;
      const double v = copy.empty() ? 0.0 : std::strtod(copy.c_str(), &endp);
      if (copy.empty() || endp != copy.c_str() + copy.size() || !std::isfinite(v))
        throw InputError(where + ": column '" + name + "': expected a finite number, got '" + shownText(f) + "'");
      return v;
    };
    TrajectorySample s;
    s.t = number("t");
    s.xy = {number("x"), number("y")};
    s.angleDeg = number("angle");
    const std::string_view id = fields[column.at("id")];
    if (id.empty()) throw InputError(where + ": column 'id': expected the vehicle's id, got an empty field");
    const std::string type = column.count("type") ? std::string(fields[column.at("type")]) : std::string();
    builder.add(std::string(id), type, s);
  }
  if (column.empty())
    throw InputError(source +
                     ": empty (expected a CSV header naming t,id,x,y,angle,type, then one row per vehicle "
                     "and time)");
  return builder.finish(source, diag);
}

glm::dvec2 forwardFromSumoAngle(double angleDeg) {
  const double a = angleDeg * kPi / 180.0;
  return {std::sin(a), std::cos(a)};
}

std::optional<GroundPose> sampleTrajectory(const Trajectory& trajectory, double t) {
  const std::vector<TrajectorySample>& s = trajectory.samples;
  if (s.empty() || !(t >= s.front().t) || !(t <= s.back().t)) return std::nullopt;
  const auto it = std::upper_bound(s.begin(), s.end(), t, [](double v, const TrajectorySample& x) { return v < x.t; });
  const std::size_t i1 = std::size_t(it - s.begin());
  const auto wrap = [](double a) {
    a = std::fmod(a, 360.0);
    return a < 0.0 ? a + 360.0 : a;
  };
  if (i1 == 0 || i1 >= s.size()) {  // t at the last sample (or a lone sample)
    const TrajectorySample& x = i1 == 0 ? s.front() : s.back();
    return GroundPose{x.xy, wrap(x.angleDeg)};
  }
  const TrajectorySample& a = s[i1 - 1];
  const TrajectorySample& b = s[i1];
  const double u = (t - a.t) / (b.t - a.t);
  // The heading the short way round: 350 -> 10 passes through 0, not 180.
  const double d = wrap(b.angleDeg - a.angleDeg + 180.0) - 180.0;
  return GroundPose{a.xy + u * (b.xy - a.xy), wrap(a.angleDeg + u * d)};
}

}  // namespace hv
