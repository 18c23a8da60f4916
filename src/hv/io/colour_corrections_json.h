// The colour corrections file (corrections.json, written by `histoview harmonize`, named by
// scene.json's "colour"): one hv::ColourCorrection per photograph id. Schema in docs/formats.md:
//
//   {"model": "gain-offset",
//    "corrections": [{"id": "p001", "gain": [1.02, 0.97, 1.0], "offset": [-0.01, 0.0, 0.02], "pairs": 5120}, ...]}
//
// A photograph shows gain * c + offset (channel by channel, straight colour in [0, 1], clamped).
#pragma once

#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <string>
#include <vector>

namespace hv {

struct ColourCorrectionEntry {
  std::string id;  // the photograph's camera id
  ColourCorrection colour;
  int pairs = -1;  // overlap pairs it was estimated from (-1: not given)
};

// Bounds a correction must keep (beyond them it is not a colour correction but a broken file).
inline constexpr double kMaxColourGain = 100.0;
inline constexpr double kMaxColourOffset = 10.0;

// Reads every entry it can; an entry with a bad field is skipped with an error naming the file,
// the entry (its id or index) and the field. Throws InputError when the text is not JSON, or not an
// object with a "corrections" array, or names another model.
std::vector<ColourCorrectionEntry> parseColourCorrections(const std::string& text, const std::string& path,
                                                          Diagnostics& diag);
std::vector<ColourCorrectionEntry> readColourCorrections(const std::string& path, Diagnostics& diag);

// Gives each photograph the correction of its id; entries naming no photograph and photographs
// without an entry (which keep the identity) are reported as warnings naming the file.
void applyColourCorrections(std::vector<Photo>& photos, const std::vector<ColourCorrectionEntry>& entries,
                            const std::string& path, Diagnostics& diag);

std::string colourCorrectionsJson(const std::vector<ColourCorrectionEntry>& entries);

}  // namespace hv
