#include "hv/util/text.h"

namespace hv {

std::string_view trimField(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
  return s;
}

std::string asciiLower(std::string_view s) {
  std::string r(s);
  for (char& c : r) c = char(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
  return r;
}

std::string shownText(std::string_view s) {
  std::string r;
  for (char c : s.substr(0, 40)) r += (c >= 32 && c < 127) ? c : '?';
  return s.size() > 40 ? r + "..." : r;
}

}  // namespace hv
