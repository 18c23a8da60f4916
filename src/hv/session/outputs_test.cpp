#include "hv/session/outputs.h"

#include <gtest/gtest.h>

#include <string>

namespace hv::app {
namespace {

// A stem is safe to append to "DIR/": it cannot name another folder, a hidden file or "." / "..".
void expectSafe(const std::string& stem) {
  EXPECT_FALSE(stem.empty());
  EXPECT_EQ(stem.find('/'), std::string::npos) << stem;
  EXPECT_EQ(stem.find('\\'), std::string::npos) << stem;
  EXPECT_EQ(stem.find('\0'), std::string::npos) << stem;
  EXPECT_NE(stem[0], '.') << stem;
  EXPECT_LE(stem.size(), kMaxStemBytes) << stem;
  for (unsigned char c : stem) EXPECT_GE(c, 0x20) << stem;
}

TEST(OutputNames, SafeIdsAreKeptAsTheyAre) {
  OutputNames names;
  std::string note = "unchanged";
  EXPECT_EQ(names.stem("view-01", &note), "view-01");
  EXPECT_EQ(note, "unchanged");  // nothing to say
  EXPECT_EQ(names.stem("rue de Rivoli 1905 é", &note), "rue de Rivoli 1905 é");
  EXPECT_EQ(names.stem("a..b"), "a..b");  // ".." inside a name is not a path component
}

TEST(OutputNames, HostileIdsStayInsideTheFolder) {
  const std::string hostile[] = {"../../x", "/tmp/x", "a/b", ".hidden", "..", ".", "", std::string(300, 'v'),
                                 std::string("nul\0byte", 8), "back\\slash", "bad\xff\xfeutf8", "ctrl\n\tchars"};
  for (const std::string& id : hostile) {
    const std::string stem = safeFileStem(id);
    expectSafe(stem);
    EXPECT_NE(stem, id);
    // Readable, and tagged with a hash of the id, so two ids that sanitise alike stay apart.
    EXPECT_EQ(stem[stem.size() - 9], '-') << stem;
  }
  EXPECT_EQ(safeFileStem("../../x").substr(0, 7), "_._.._x");
  EXPECT_EQ(safeFileStem("/tmp/x").substr(0, 6), "_tmp_x");
  EXPECT_NE(safeFileStem("a/b"), safeFileStem("a\\b"));  // same text, different hash
}

TEST(OutputNames, LongIdsAreCutOnACharacterBoundary) {
  std::string id;
  for (int i = 0; i < 100; ++i) id += "é";  // 200 bytes of 2-byte characters
  const std::string stem = safeFileStem(id);
  expectSafe(stem);
  const std::string text = stem.substr(0, stem.size() - 9);
  EXPECT_EQ(text.size() % 2, 0u);  // no character cut in half
  for (size_t i = 0; i < text.size(); i += 2) EXPECT_EQ(text.substr(i, 2), "é");
}

TEST(OutputNames, CollisionsGetASuffixAndANote) {
  OutputNames names;
  EXPECT_EQ(names.stem("v"), "v");
  std::string note;
  EXPECT_EQ(names.stem("v", &note), "v-2");
  EXPECT_NE(note.find("'v'"), std::string::npos) << note;
  EXPECT_NE(note.find("v-2"), std::string::npos) << note;
  EXPECT_NE(note.find("already"), std::string::npos) << note;
  EXPECT_EQ(names.stem("V"), "V-3");  // a case-folding file system would overwrite v
  EXPECT_EQ(names.stem("v-2"), "v-2-2");
  // A hostile id that sanitises to a name already used also gets a suffix.
  const std::string first = names.stem("a/b");
  EXPECT_NE(names.stem("a/b"), first);
}

TEST(OutputNames, ExitStatusPolicy) {
  Diagnostics diag;
  EXPECT_EQ(exitStatus(diag), kExitOk);
  diag.warnings.push_back("a warning");
  EXPECT_EQ(exitStatus(diag), kExitOk);  // warnings never change the status
  diag.errors.push_back("a camera left out");
  EXPECT_EQ(exitStatus(diag), kExitLeftOut);
  EXPECT_EQ(exitStatus(diag, 1), kExitNotProduced);
  EXPECT_EQ(exitStatus(Diagnostics{}, 2), kExitNotProduced);
}

}  // namespace
}  // namespace hv::app
