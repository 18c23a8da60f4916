#include "hv/util/diagnostics.h"

#include "hv/util/log.h"

#include <fstream>

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

std::vector<std::uint8_t> readFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(inputMessage(path, "", "cannot open the file"));
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  in.seekg(0, std::ios::beg);
  std::vector<std::uint8_t> bytes(size > 0 ? std::size_t(size) : 0);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size())))
    throw InputError(inputMessage(path, "", "read error"));
  return bytes;
}

}  // namespace hv
