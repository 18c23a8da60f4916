// The colour corrections file (hv/io/colour_corrections_json.h): written, read back, and bad
// input reported by file, entry and field while the rest loads.
#include "hv/io/colour_corrections_json.h"

#include <gtest/gtest.h>

namespace hv {
namespace {

bool mentions(const std::vector<std::string>& messages, const std::string& part) {
  for (const std::string& m : messages)
    if (m.find(part) != std::string::npos) return true;
  return false;
}

TEST(ColourCorrectionsJson, RoundTrips) {
  ColourCorrectionEntry a{"p001", {{1.25, 0.9, 1.0}, {-0.125, 0.05, 0.0}}, 512};
  ColourCorrectionEntry b{"p002", {}, -1};
  Diagnostics diag;
  const auto back = parseColourCorrections(colourCorrectionsJson({a, b}), "c.json", diag);
  EXPECT_TRUE(diag.ok());
  EXPECT_TRUE(diag.warnings.empty());
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].id, "p001");
  EXPECT_EQ(back[0].colour.gain, a.colour.gain);
  EXPECT_EQ(back[0].colour.offset, a.colour.offset);
  EXPECT_EQ(back[0].pairs, 512);
  EXPECT_TRUE(back[1].colour.isIdentity());
  EXPECT_EQ(back[1].pairs, -1);
}

TEST(ColourCorrectionsJson, BadEntriesAreNamedAndTheRestLoads) {
  const std::string text = R"({"model": "gain-offset", "corrections": [
    {"id": "good", "gain": [2, 1, 0.5], "offset": [0, 0.1, -0.1]},
    {"id": "short", "gain": [1, 1], "offset": [0, 0, 0]},
    {"id": "text", "gain": [1, 1, 1], "offset": [0, "a", 0]},
    {"id": "huge", "gain": [1e9, 1, 1], "offset": [0, 0, 0]},
    {"id": "negative", "gain": [-1, 1, 1], "offset": [0, 0, 0]},
    {"gain": [1, 1, 1], "offset": [0, 0, 0]},
    {"id": "good", "gain": [1, 1, 1], "offset": [0, 0, 0]},
    {"id": "nooffset", "gain": [1, 1, 1], "ofset": [0, 0, 0]},
    3]})";
  Diagnostics diag;
  const auto entries = parseColourCorrections(text, "c.json", diag);
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries[0].id, "good");
  EXPECT_EQ(entries[0].colour.gain, glm::dvec3(2, 1, 0.5));
  EXPECT_EQ(diag.errors.size(), 8u);
  EXPECT_TRUE(mentions(diag.errors, "c.json: corrections[1] ('short'): gain: expected an array of 3 numbers"));
  EXPECT_TRUE(mentions(diag.errors, "('text'): offset: expected numbers"));
  EXPECT_TRUE(mentions(diag.errors, "('huge'): gain: expected finite numbers in [0.0, 100.0]"));
  EXPECT_TRUE(mentions(diag.errors, "('negative'): gain"));
  EXPECT_TRUE(mentions(diag.errors, "corrections[5]: id: expected a non-empty string"));
  EXPECT_TRUE(mentions(diag.errors, "corrections[6] ('good'): id: repeated"));
  EXPECT_TRUE(mentions(diag.errors, "('nooffset'): offset: missing"));
  EXPECT_TRUE(mentions(diag.warnings, "unknown key 'ofset' (did you mean 'offset'?)"));
  EXPECT_TRUE(mentions(diag.errors, "corrections[8]: expected an object"));
}

TEST(ColourCorrectionsJson, WholeFileProblemsThrowNamingTheFile) {
  Diagnostics diag;
  for (const char* text : {"", "[1, 2]", "{\"corrections\": 3}", "{}", "{\"model\": \"matrix\", \"corrections\": []}",
                           "{\"corrections\": [}"}) {
    try {
      parseColourCorrections(text, "bad.json", diag);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
    }
  }
}

TEST(ColourCorrectionsJson, AppliedByPhotographId) {
  std::vector<Photo> photos(3);
  photos[0].camera.id = "a";
  photos[1].camera.id = "b";
  photos[2].camera.id = "c";
  const std::vector<ColourCorrectionEntry> entries = {{"b", {{1.5, 1, 1}, {0, 0, 0.25}}, 3},
                                                      {"z", {{2, 2, 2}, {0, 0, 0}}, 3}};
  Diagnostics diag;
  applyColourCorrections(photos, entries, "c.json", diag);
  EXPECT_TRUE(photos[0].colour.isIdentity());
  EXPECT_EQ(photos[1].colour.gain.r, 1.5);
  EXPECT_EQ(photos[1].colour.offset.b, 0.25);
  EXPECT_TRUE(photos[2].colour.isIdentity());
  EXPECT_TRUE(diag.ok());
  EXPECT_TRUE(mentions(diag.warnings, "c.json: corrections: 1 entry names no photograph of the scene (first: 'z')"));
  EXPECT_TRUE(mentions(diag.warnings, "2 photographs without a correction keep their colours"));
  // The correction as the renderer applies it: gain c + offset, clamped.
  EXPECT_EQ(photos[1].colour.apply({0.5, 0.5, 0.9}), glm::dvec3(0.75, 0.5, 1.0));
}

}  // namespace
}  // namespace hv
