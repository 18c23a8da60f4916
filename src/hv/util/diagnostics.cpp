#include "hv/util/diagnostics.h"

#include "hv/util/log.h"


namespace hv {

void Diagnostics::warn(std::string message) {
  log::warn(message);
  warnings.push_back(std::move(message));
}

void Diagnostics::error(std::string message) {
  log::error(message);
  errors.push_back(std::move(message));
}

void Diagnostics::merge(const Diagnostics& other) {
  warnings.insert(warnings.end(), other.warnings.begin(), other.warnings.end());
  errors.insert(errors.end(), other.errors.begin(), other.errors.end());
}

std::string inputMessage(const std::string& file, const std::string& field, const std::string& message) {
  std::string out = file;
  if (!field.empty()) out += (out.empty() ? "" : ": ") + field;
  return out + ": " + message;
}

}  // namespace hv
