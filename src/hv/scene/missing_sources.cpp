#include "hv/scene/missing_sources.h"

#include <algorithm>
#include <map>

namespace hv {

void MissingSources::add(MissingSource s) {
  if (!s.location.empty() && s.reason.size() > s.location.size() + 2 && s.reason.rfind(s.location + ": ", 0) == 0)
    s.reason.erase(0, s.location.size() + 2);
  if (s.attempts < 1) s.attempts = 1;
  const std::lock_guard<std::mutex> lock(mutex_);
  ++version_;
  for (MissingSource& m : items_)
    if (m.kind == s.kind && m.location == s.location) {
      m = std::move(s);
      return;
    }
  items_.push_back(std::move(s));
}

bool MissingSources::resolve(const std::string& kind, const std::string& location) {
  const std::lock_guard<std::mutex> lock(mutex_);
  const auto it = std::find_if(items_.begin(), items_.end(),
                               [&](const MissingSource& m) { return m.kind == kind && m.location == location; });
  if (it == items_.end()) return false;
  items_.erase(it);
  ++version_;
  return true;
}

void MissingSources::clear() {
  const std::lock_guard<std::mutex> lock(mutex_);
  items_.clear();
  ++version_;
}

std::vector<MissingSource> MissingSources::list() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return items_;
}

std::size_t MissingSources::size() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return items_.size();
}

std::size_t MissingSources::version() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return version_;
}

std::string describeMissing(const MissingSource& s) {
  std::string line = s.location.empty() ? s.reason : s.location + ": " + s.reason;
  if (s.retrying)
    line += " (retrying, " + std::to_string(s.attempts) + (s.attempts == 1 ? " try)" : " tries)");
  else if (s.attempts > 1)
    line += " (" + std::to_string(s.attempts) + " tries, given up)";
  return line;
}

std::vector<std::string> MissingSources::lines() const {
  std::vector<std::string> out;
  for (const MissingSource& s : list()) out.push_back(s.kind + ": " + describeMissing(s));
  return out;
}

std::string MissingSources::summary() const {
  const std::vector<MissingSource> items = list();
  if (items.empty()) return "";
  // Kinds in the order first seen.
  std::vector<std::string> kinds;
  std::map<std::string, std::vector<const MissingSource*>> byKind;
  for (const MissingSource& s : items) {
    if (!byKind.count(s.kind)) kinds.push_back(s.kind);
    byKind[s.kind].push_back(&s);
  }
  std::string out = "missing: ";
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    const auto& of = byKind[kinds[k]];
    if (k) out += ", ";
    if (of.size() == 1) {
      out += kinds[k] + (of[0]->location.empty() ? "" : " (" + of[0]->location + ")");
    } else {
      // "photograph" -> "2 photographs", "building tile" -> "3 building tiles".
      out += std::to_string(of.size()) + " " + kinds[k] + "s";
    }
    std::size_t retrying = 0;
    for (const MissingSource* s : of) retrying += s->retrying;
    if (retrying) out += retrying == of.size() ? " retrying" : " (" + std::to_string(retrying) + " retrying)";
  }
  return out;
}

}  // namespace hv
