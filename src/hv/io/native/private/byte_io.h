// Little- and big-endian loads and stores of fixed-size numbers from byte buffers, independent of
// the host's byte order and alignment. The caller checks bounds; these only move bytes.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>

namespace hv::bytes {

template <typename T>
T load(const std::uint8_t* p, bool bigEndian = false) {
  static_assert(std::is_arithmetic_v<T>);
  std::uint8_t b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (bigEndian != (std::endian::native == std::endian::big))
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

template <typename T>
void storeLE(std::uint8_t* p, T v) {
  static_assert(std::is_arithmetic_v<T>);
  std::memcpy(p, &v, sizeof(T));
  if constexpr (std::endian::native == std::endian::big)
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(p[i], p[sizeof(T) - 1 - i]);
}

template <typename T>
void appendLE(std::string& out, T v) {
  std::uint8_t b[sizeof(T)];
  storeLE(b, v);
  out.append(reinterpret_cast<const char*>(b), sizeof(T));
}

}  // namespace hv::bytes
