// Reading input files safely: what every reader checks before it opens a file, and the caps on
// what it takes in (docs/formats.md, "Limits"). hv::readFileBytes (diagnostics.h) goes through the
// same checks.
#pragma once

#include "hv/util/diagnostics.h"

#include <cstdint>
#include <string>
#include <vector>

namespace hv {

// Caps on what the readers take in (docs/formats.md, "Limits"): a file over its cap is refused,
// naming the file and its size, before anything is allocated for it.
constexpr std::uint64_t kMaxJsonBytes = std::uint64_t(256) << 20;   // scene.json, cameras, --views, iTowns
constexpr std::uint64_t kMaxTextBytes = std::uint64_t(256) << 20;   // COLMAP text, MicMac XML
constexpr std::uint64_t kMaxBinaryBytes = std::uint64_t(16) << 30;  // LAS, PLY point clouds read whole
constexpr std::uint64_t kMaxImageBytes = std::uint64_t(1) << 30;    // a photograph or mask fetched by URL

// Why `path` cannot be read as a regular file, or "" when it can: not found, a directory, a FIFO,
// socket or device, a symbolic-link loop, a name too long, a NUL byte in the path. Never throws and
// never opens the file (a FIFO would block the open until a writer comes).
std::string notRegularFileReason(const std::string& path);
// True when `path` is a regular file (or a link to one); never throws.
bool isRegularFile(const std::string& path);

// Throws InputError "<path>: <what>: <reason>" unless `path` is a regular file of at most
// `maxBytes`; returns its size. `what` names what the file is for ("cameras file", "terrain").
std::uint64_t requireRegularFile(const std::string& path, const std::string& what, std::uint64_t maxBytes = UINT64_MAX);

// Sources that are not local files (docs/services.md, "Paths"). A GDAL user names a service the
// way GDAL does: "WFS:http://...", "WCS:http://...", "OAPIF:http://...", "PG:...", "/vsicurl/...",
// "http(s)://...". True when `path` has that form: GDAL's virtual-file prefix "/vsi", a URL scheme
// ("name://"), or a driver prefix of two or more letters, digits or '_' before a ':' ("C:" is a
// drive letter, not a driver). Looks at the string only.
bool isConnectionString(const std::string& path);

// The path a scene.json source names, as the readers take it: a path that exists locally (relative
// ones against `dir`, scene.json's folder) is that local path, whatever it looks like; else a
// connection string is handed on as it is; else the local path (whose reader then says "file not
// found").
std::string resolveSourcePath(const std::string& path, const std::string& dir);

// True when `path` is a connection string that names no local file: what GDAL opens, or what the
// remote reader below fetches.
bool isRemoteSource(const std::string& path);

// True when `path` is an http:// or https:// URL (any case): what a photograph or mask may be.
bool isHttpUrl(const std::string& path);

// Whether a remote response may come from (and go into) histoview's response cache
// (docs/services.md, "Cache"): photographs, masks and IIIF descriptions may; sources that change
// (cameras, features) are always asked again.
enum class RemoteCache { No, Yes };

// Reads a remote source whole (`what` and the cap as for readTextFile), throwing InputError naming
// the URL. The native io module installs one (hv/io/native/remote.h, through GDAL's HTTP client);
// without one, readTextFile, readFileBytes and readInputBytes refuse a remote source.
using RemoteReader = std::string (*)(const std::string& path, std::uint64_t maxBytes, const std::string& what,
                                     RemoteCache cache);
void setRemoteReader(RemoteReader reader);

// The whole of a binary input, a local file or a remote source (through the remote reader, with
// `cache`), refused (InputError naming it, what it is for and the size) over `maxBytes`.
std::vector<std::uint8_t> readInputBytes(const std::string& path, std::uint64_t maxBytes, const std::string& what,
                                         RemoteCache cache = RemoteCache::No);

// The whole of a text input, refused (InputError naming the file, what it is for and the size)
// when it is not a regular file or is larger than `maxBytes`.
std::string readTextFile(const std::string& path, std::uint64_t maxBytes, const std::string& what);

// The candidate nearest to a misspelt `word` (edit distance, at most 3 and at most half the
// longer word), or "" when none is near: for "did you mean 'distortion'?" hints.
std::string closestName(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace hv
