// Fuzz target: the text forms of the camera layers' number fields (hv::parseNumber,
// hv::parseNumberList: "{a,b,...}" from PostgreSQL, "[a,b,...]" from JSON). Whatever the text, the
// answer is nothing or finite numbers, and a list's numbers are what parseNumber reads of its items.
#include "hv/io/native/camera_catalog.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  if (const auto v = hv::parseNumber(text); v && !std::isfinite(*v)) {
    std::fprintf(stderr, "number_list: BUG: a non-finite number read\n");
    std::abort();
  }
  if (const auto list = hv::parseNumberList(text)) {
    std::size_t commas = 0;
    for (char ch : text) commas += ch == ',';
    if (!list->empty() && list->size() != commas + 1) {
      std::fprintf(stderr, "number_list: BUG: %zu numbers from %zu commas\n", list->size(), commas);
      std::abort();
    }
    for (double d : *list)
      if (!std::isfinite(d)) {
        std::fprintf(stderr, "number_list: BUG: a non-finite number in a list\n");
        std::abort();
      }
  }
  return 0;
}
