// Diagnostics: how loaders report bad input without stopping.
//
// Rule of the project: a broken file, camera, image or tile never crashes the program and never
// stops the rest of the scene from loading. Loaders record an error that names the file, the field
// and what was expected, skip the broken item, and go on. Callers decide what is fatal.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace hv {

// Thrown by parsers for an input that cannot be read at all; caught at the item boundary
// (one camera, one feature, one file) and turned into a Diagnostics entry.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Diagnostics {
  std::vector<std::string> warnings;
  std::vector<std::string> errors;

  void warn(std::string message);
  void error(std::string message);
  bool ok() const { return errors.empty(); }
  // Appends another collection (e.g. a sub-loader's) to this one.
  void merge(const Diagnostics& other);
};

// Formats "file: field: message" the one way the project spells input errors.
std::string inputMessage(const std::string& file, const std::string& field, const std::string& message);

// The whole file as bytes (binary readers parse from memory). Throws InputError naming the file
// when it cannot be opened or read.
std::vector<std::uint8_t> readFileBytes(const std::string& path);

}  // namespace hv
