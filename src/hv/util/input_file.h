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
constexpr std::uint64_t kMaxJsonBytes = std::uint64_t(256) << 20;  // scene.json, cameras, --views, iTowns
constexpr std::uint64_t kMaxTextBytes = std::uint64_t(256) << 20;  // COLMAP text, MicMac XML
constexpr std::uint64_t kMaxBinaryBytes = std::uint64_t(16) << 30;  // LAS, PLY point clouds read whole

// Why `path` cannot be read as a regular file, or "" when it can: not found, a directory, a FIFO,
// socket or device, a symbolic-link loop, a name too long, a NUL byte in the path. Never throws and
// never opens the file (a FIFO would block the open until a writer comes).
std::string notRegularFileReason(const std::string& path);
// True when `path` is a regular file (or a link to one); never throws.
bool isRegularFile(const std::string& path);

// Throws InputError "<path>: <what>: <reason>" unless `path` is a regular file of at most
// `maxBytes`; returns its size. `what` names what the file is for ("cameras file", "terrain").
std::uint64_t requireRegularFile(const std::string& path, const std::string& what,
                                 std::uint64_t maxBytes = UINT64_MAX);

// The whole of a text input, refused (InputError naming the file, what it is for and the size)
// when it is not a regular file or is larger than `maxBytes`.
std::string readTextFile(const std::string& path, std::uint64_t maxBytes, const std::string& what);

// The candidate nearest to a misspelt `word` (edit distance, at most 3 and at most half the
// longer word), or "" when none is near: for "did you mean 'distortion'?" hints.
std::string closestName(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace hv
