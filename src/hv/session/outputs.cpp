#include "hv/session/outputs.h"

#include "hv/io/native/remote.h"
#include "hv/util/image_sizes.h"

#include <cstdint>
#include <cstdio>

namespace hv::app {

namespace {

// FNV-1a, 32 bits: a short, stable tag telling apart ids that sanitise to the same text.
std::uint32_t fnv1a(const std::string& s) {
  std::uint32_t h = 2166136261u;
  for (unsigned char c : s) {
    h ^= c;
    h *= 16777619u;
  }
  return h;
}

// Bytes of the UTF-8 sequence starting at s[i] (1..4), or 0 when it is not a valid one
// (overlong forms, surrogates and code points above U+10FFFF included).
std::size_t utf8Length(const std::string& s, std::size_t i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = b(i);
  if (c < 0x80) return 1;
  std::size_t n = 0;
  std::uint32_t cp = 0;
  if ((c & 0xe0) == 0xc0)
    n = 2, cp = c & 0x1f;
  else if ((c & 0xf0) == 0xe0)
    n = 3, cp = c & 0x0f;
  else if ((c & 0xf8) == 0xf0)
    n = 4, cp = c & 0x07;
  else
    return 0;
  if (i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k) {
    if ((b(i + k) & 0xc0) != 0x80) return 0;
    cp = (cp << 6) | (b(i + k) & 0x3f);
  }
  const std::uint32_t least[5] = {0, 0, 0x80, 0x800, 0x10000};
  if (cp < least[n] || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return 0;
  return n;
}

std::string lower(std::string s) {
  for (char& c : s)
    if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
  return s;
}

}  // namespace

bool validUtf8(const std::string& text) {
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t n = utf8Length(text, i);
    if (n == 0) return false;
    i += n;
  }
  return true;
}

int exitStatus(const Diagnostics& diag, std::size_t notProduced) {
  if (notProduced > 0) return kExitNotProduced;
  return diag.ok() ? kExitOk : kExitLeftOut;
}

const char* exitStatusHelp() {
  return "Exit status (docs/reliability.md): 0 everything asked for was produced and nothing was left out; "
         "3 produced, but some input items (cameras, photographs, masks, footprints, tiles) failed validation "
         "or decoding and were left out, each named once; 1 something asked for could not be produced; 2 the "
         "scene cannot be loaded. Warnings, notes, --exclude and K above the photographs available never change "
         "it. --strict: stop with 1 before rendering when anything would be left out.";
}

std::string safeFileStem(const std::string& id) {
  std::string out;
  out.reserve(id.size());
  for (std::size_t i = 0; i < id.size();) {
    const std::size_t n = utf8Length(id, i);
    const unsigned char c = static_cast<unsigned char>(id[i]);
    if (n == 0 || c < 0x20 || c == 0x7f || c == '/' || c == '\\') {
      out += '_';  // a separator, a control character (NUL included) or a byte that is not UTF-8
      i += n == 0 ? 1 : n;
      continue;
    }
    out.append(id, i, n);
    i += n;
  }
  if (out.empty()) out = "_";
  if (out[0] == '.') out[0] = '_';  // ".", "..", hidden files
  const bool changed = out != id;
  const bool tooLong = out.size() > kMaxStemBytes;
  if (!changed && !tooLong) return out;
  char tag[16];
  std::snprintf(tag, sizeof tag, "-%08x", unsigned(fnv1a(id)));
  std::size_t keep = kMaxStemBytes - 9;
  if (out.size() > keep) {
    while (keep > 0 && (static_cast<unsigned char>(out[keep]) & 0xc0) == 0x80) --keep;  // whole characters
    out.resize(keep);
  }
  return out + tag;
}

std::string OutputNames::stem(const std::string& id, std::string* note) {
  const std::string base = safeFileStem(id);
  std::string name = base;
  for (int k = 2; used_.count(lower(name)); ++k) name = base + "-" + std::to_string(k);
  used_.insert(lower(name));
  if (note && name != id) {
    std::string shown;
    for (unsigned char c : id) {  // the id as text the terminal can show
      if (c < 0x20 || c == 0x7f) {
        char hex[8];
        std::snprintf(hex, sizeof hex, "\\x%02x", unsigned(c));
        shown += hex;
      } else {
        shown += char(c);
      }
    }
    *note = "id '" + shown + "' written as '" + name + "' (" +
            (name != base ? std::string("another output of this folder already has its name")
                          : std::string("a file name must stay inside the output folder: no separators, no "
                                        "leading dot, no control characters, valid UTF-8, at most " +
                                        std::to_string(kMaxStemBytes) + " bytes")) +
            ")";
  }
  return name;
}

std::string fetchedSummary() {
  const ImageFetchCounts images = imageFetchCounts();
  const RemoteFetchCounts remote = remoteFetchCounts();
  std::string out;
  if (images.previews + images.images > 0)
    out += "photographs read by URL: " + std::to_string(images.previews) + " previews, " +
           std::to_string(images.previewBytes) + " bytes; " + std::to_string(images.images) + " full images, " +
           std::to_string(images.imageBytes) + " bytes\n";
  if (remote.fetched + remote.cached > 0)
    out += "http(s) responses: " + std::to_string(remote.fetched) + " fetched, " + std::to_string(remote.fetchedBytes) +
           " bytes; " + std::to_string(remote.cached) + " from the response cache, " +
           std::to_string(remote.cachedBytes) + " bytes\n";
  return out;
}

}  // namespace hv::app
