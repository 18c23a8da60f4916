// What every command writes and how it ends (docs/reliability.md): file names derived from ids
// (view, camera, frame) made safe to write into the command's output folder, and the one policy
// for exit statuses.
#pragma once

#include "hv/util/diagnostics.h"

#include <cstddef>
#include <set>
#include <string>

namespace hv::app {

// Exit statuses, the same for every command (docs/reliability.md, `histoview --help`).
enum ExitStatus : int {
  kExitOk = 0,           // everything asked for was produced, nothing left out
  kExitNotProduced = 1,  // something asked for could not be produced (or `check`: something would be left out)
  kExitNoScene = 2,      // the scene (or the command's main input) cannot be loaded
  kExitLeftOut = 3,      // everything asked for was produced, some input items were left out
};

// `notProduced`: outputs asked for that could not be written; diag.errors: input items (camera,
// photograph, mask, footprint, tile...) that failed validation or decoding and were left out.
// Warnings and notes never change the status.
int exitStatus(const Diagnostics& diag, std::size_t notProduced = 0);

// The policy in a few lines, for `--help` and the messages.
const char* exitStatusHelp();

// What the command read over http(s) (docs/services.md, "Photographs by URL and IIIF"): one line
// of the photographs the renderer's image loader read, previews (a IIIF image service's small
// size) apart from full images, and one of the responses fetched from servers and read from the
// response cache. "" when nothing was read remotely.
std::string fetchedSummary();

// Longest stem outputFileName returns, in bytes: with a command's longest suffix
// (".count-preview.png") it stays well under the 255 bytes of common file systems.
inline constexpr std::size_t kMaxStemBytes = 120;

// Makes file-name stems (no extension) from ids, one per output, within one folder: the id as it
// is when it is safe and unused; otherwise a readable version of it plus "-" and 8 hex digits of
// a hash of the id. Safe means: no '/' or '\\', no NUL or other control character, valid UTF-8, no
// leading '.' (so neither "." nor ".." nor a hidden file), not empty, at most kMaxStemBytes
// bytes. Used means: an earlier stem of this folder equal to it ignoring ASCII case (file systems
// that fold case would overwrite it); a used stem gets "-2", "-3", ...
class OutputNames {
 public:
  // The stem for `id`; `note` (when non-null and the stem is not the id) receives a sentence
  // naming the id and the stem, for the command to print once.
  std::string stem(const std::string& id, std::string* note = nullptr);

 private:
  std::set<std::string> used_;  // folded to lower case
};

// True when `text` is valid UTF-8 (JSON, which the web export and `cameras convert` write, can
// hold nothing else).
bool validUtf8(const std::string& text);

// The sanitising alone (no collision handling): the safe stem of one id.
std::string safeFileStem(const std::string& id);

}  // namespace hv::app
