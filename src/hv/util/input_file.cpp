#include "hv/util/input_file.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <system_error>

namespace hv {

namespace fs = std::filesystem;

std::string notRegularFileReason(const std::string& path) {
  if (path.empty()) return "empty path";
  // The system calls would stop at the NUL and open another file than the one named.
  if (path.find('\0') != std::string::npos) return "the path contains a NUL byte";
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);  // stat(2): follows links, opens nothing
  if (ec) {
    if (ec == std::errc::no_such_file_or_directory || ec == std::errc::not_a_directory) return "file not found";
    if (ec == std::errc::too_many_symbolic_link_levels) return "a loop of symbolic links";
    if (ec == std::errc::filename_too_long) return "the name is too long for the file system";
    return "cannot be examined: " + ec.message();
  }
  switch (st.type()) {
    case fs::file_type::regular:
      return "";
    case fs::file_type::not_found:
      return "file not found";
    case fs::file_type::directory:
      return "a directory, not a file";
    case fs::file_type::fifo:
      return "a FIFO (named pipe), not a regular file";
    case fs::file_type::socket:
      return "a socket, not a regular file";
    case fs::file_type::character:
    case fs::file_type::block:
      return "a device, not a regular file";
    default:
      return "not a regular file";
  }
}

bool isRegularFile(const std::string& path) { return notRegularFileReason(path).empty(); }

bool isConnectionString(const std::string& path) {
  if (path.find('\0') != std::string::npos) return false;
  if (path.rfind("/vsi", 0) == 0) return true;
  const std::size_t colon = path.find(':');
  if (colon == std::string::npos || colon < 2) return false;
  if (!std::isalpha(static_cast<unsigned char>(path[0]))) return false;
  for (std::size_t i = 1; i < colon; ++i) {
    const unsigned char c = static_cast<unsigned char>(path[i]);
    // A URL scheme may hold '+', '-' and '.' ("svn+ssh"); GDAL's prefixes are letters, digits, '_'.
    if (!std::isalnum(c) && c != '_' && c != '+' && c != '-' && c != '.') return false;
  }
  return true;
}

namespace {

bool existsLocally(const fs::path& p) {
  std::error_code ec;
  // symlink_status: a dangling link is there too (and refused by the reader, naming it).
  return fs::symlink_status(p, ec).type() != fs::file_type::not_found && !ec;
}

std::atomic<RemoteReader> gRemoteReader{nullptr};

}  // namespace

std::string resolveSourcePath(const std::string& path, const std::string& dir) {
  if (path.empty() || path.find('\0') != std::string::npos) return path;
  const fs::path p = path;
  const std::string local = (p.is_absolute() ? p : fs::path(dir) / p).lexically_normal().string();
  if (existsLocally(local)) return local;
  if (isConnectionString(path)) return path;
  return local;
}

bool isRemoteSource(const std::string& path) { return isConnectionString(path) && !existsLocally(path); }

void setRemoteReader(RemoteReader reader) { gRemoteReader.store(reader); }

namespace {

std::string sizeText(std::uint64_t bytes) {
  if (bytes >= (std::uint64_t(1) << 20))
    return std::to_string(bytes >> 20) + " MiB (" + std::to_string(bytes) + " bytes)";
  return std::to_string(bytes) + " bytes";
}

}  // namespace

std::uint64_t requireRegularFile(const std::string& path, const std::string& what, std::uint64_t maxBytes) {
  const std::string reason = notRegularFileReason(path);
  if (!reason.empty()) {
    // A message is a C string in the end (what()): a NUL would cut it, so it is spelt out.
    std::string shown;
    for (char c : path) shown += c == '\0' ? std::string("\\0") : std::string(1, c);
    throw InputError(inputMessage(shown, what, reason));
  }
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw InputError(inputMessage(path, what, "cannot be examined: " + ec.message()));
  if (size > maxBytes)
    throw InputError(inputMessage(path, what,
                                  "the file is " + sizeText(size) + ", over the limit of " + sizeText(maxBytes) +
                                      " for this input (docs/formats.md, Limits)"));
  return size;
}

namespace {

// Reads at most `maxBytes` + 1 bytes: a file that grew since it was examined is still refused.
template <class Bytes>
Bytes readCapped(const std::string& path, std::uint64_t maxBytes, const std::string& what,
                 RemoteCache cache = RemoteCache::No) {
  if (isRemoteSource(path)) {
    const RemoteReader reader = gRemoteReader.load();
    if (!reader)
      throw InputError(inputMessage(path, what, "a URL or connection string, and this build reads local files only"));
    const std::string text = reader(path, maxBytes, what, cache);
    return Bytes(text.begin(), text.end());
  }
  const std::uint64_t size = requireRegularFile(path, what, maxBytes);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(inputMessage(path, what, "cannot open the file"));
  Bytes bytes(size_t(size), 0);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size())))
    throw InputError(inputMessage(path, what, "read error (the file shrank or cannot be read)"));
  char extra;
  if (in.read(&extra, 1) && size + 1 > maxBytes)
    throw InputError(
        inputMessage(path, what, "the file grew over the limit of " + sizeText(maxBytes) + " while it was read"));
  if (in.gcount() == 1) {  // grew but still under the cap: read the rest, capped
    bytes.push_back(static_cast<typename Bytes::value_type>(extra));
    char buf[1 << 16];
    while (in.read(buf, sizeof buf) || in.gcount() > 0) {
      if (bytes.size() + std::uint64_t(in.gcount()) > maxBytes)
        throw InputError(
            inputMessage(path, what, "the file grew over the limit of " + sizeText(maxBytes) + " while it was read"));
      bytes.insert(bytes.end(), buf, buf + in.gcount());
    }
  }
  return bytes;
}

}  // namespace

std::string readTextFile(const std::string& path, std::uint64_t maxBytes, const std::string& what) {
  return readCapped<std::string>(path, maxBytes, what);
}

std::vector<std::uint8_t> readInputBytes(const std::string& path, std::uint64_t maxBytes, const std::string& what,
                                         RemoteCache cache) {
  return readCapped<std::vector<std::uint8_t>>(path, maxBytes, what, cache);
}

bool isHttpUrl(const std::string& path) {
  const auto startsWith = [&](const char* prefix) {
    const std::size_t n = std::char_traits<char>::length(prefix);
    if (path.size() < n) return false;
    for (std::size_t i = 0; i < n; ++i)
      if (std::tolower(static_cast<unsigned char>(path[i])) != prefix[i]) return false;
    return true;
  };
  return startsWith("http://") || startsWith("https://");
}

std::vector<std::uint8_t> readFileBytes(const std::string& path) {
  return readCapped<std::vector<std::uint8_t>>(path, kMaxBinaryBytes, "");
}

std::string closestName(const std::string& word, const std::vector<std::string>& candidates) {
  // Levenshtein distance, case-insensitive; one row at a time.
  const auto lower = [](char c) { return char(std::tolower(static_cast<unsigned char>(c))); };
  const auto distance = [&](const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
      size_t diagonal = row[0];
      row[0] = i;
      for (size_t j = 1; j <= b.size(); ++j) {
        const size_t up = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1)});
        diagonal = up;
      }
    }
    return row[b.size()];
  };
  if (word.size() > 64) return "";
  std::string best;
  size_t bestDistance = SIZE_MAX;
  for (const std::string& c : candidates) {
    const size_t d = distance(word, c);
    if (d <= 3 && 2 * d <= std::max(word.size(), c.size()) && d < bestDistance) {
      best = c;
      bestDistance = d;
    }
  }
  return best;
}

}  // namespace hv
