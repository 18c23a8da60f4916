#include "hv/util/diagnostics.h"
#include "hv/util/input_file.h"
#include "hv/util/log.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace hv {
namespace {

namespace fs = std::filesystem;

class FileChecks : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hv_diagnostics_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

// Expects readTextFile to refuse `p` at once with a message naming the file and `reason`.
void expectRefused(const std::string& p, const std::string& reason) {
  try {
    readTextFile(p, kMaxJsonBytes, "cameras file");
    FAIL() << p << " was read";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(p.substr(0, p.find('\0'))), std::string::npos) << what;  // a NUL is shown as \0
    EXPECT_NE(what.find(reason), std::string::npos) << what;
  }
}

TEST_F(FileChecks, ReadsARegularFile) {
  std::ofstream(path("a.json")) << "{\"cameras\": []}";
  EXPECT_EQ(readTextFile(path("a.json"), kMaxJsonBytes, "cameras file"), "{\"cameras\": []}");
  EXPECT_TRUE(isRegularFile(path("a.json")));
}

TEST_F(FileChecks, RefusesAFifoWithoutOpeningIt) {
  // Opening a FIFO blocks until a writer comes: the check must come before any open.
  ASSERT_EQ(::mkfifo(path("pipe").c_str(), 0600), 0);
  expectRefused(path("pipe"), "FIFO");
  EXPECT_FALSE(isRegularFile(path("pipe")));
}

TEST_F(FileChecks, RefusesDevicesDirectoriesAndMissingFiles) {
  expectRefused("/dev/zero", "a device");
  expectRefused(dir_.string(), "a directory");
  expectRefused(path("missing.json"), "file not found");
}

TEST_F(FileChecks, NamesSymlinkLoopsLongNamesAndNulBytes) {
  fs::create_symlink(path("loop_b"), path("loop_a"));
  fs::create_symlink(path("loop_a"), path("loop_b"));
  expectRefused(path("loop_a"), "loop of symbolic links");
  EXPECT_FALSE(isRegularFile(path("loop_a")));  // no filesystem_error escapes
  expectRefused(path(std::string(300, 'x') + ".json"), "name is too long");
  std::ofstream(path("a.json")) << "{}";
  expectRefused(path("a.json") + std::string(1, '\0') + "tail",
                "a.json\\0tail: cameras file: the path contains a NUL byte");
}

TEST_F(FileChecks, RefusesFilesOverTheCapBeforeReadingThem) {
  // Sparse: 300 MiB on paper, no block on disk; refused by its size, not by running out of memory.
  const std::string big = path("big.json");
  std::ofstream(big).close();
  fs::resize_file(big, std::uintmax_t(300) << 20);
  try {
    readTextFile(big, kMaxJsonBytes, "scene");
    FAIL() << "read";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(big), std::string::npos) << what;
    EXPECT_NE(what.find("300 MiB"), std::string::npos) << what;
    EXPECT_NE(what.find("256 MiB"), std::string::npos) << what;
  }
  std::ofstream(path("small.txt")) << "0123456789";
  EXPECT_THROW(readTextFile(path("small.txt"), 9, "test"), InputError);
  EXPECT_EQ(readTextFile(path("small.txt"), 10, "test"), "0123456789");
}

TEST(ClosestName, SuggestsNearKeysOnly) {
  const std::vector<std::string> keys = {"id", "image", "mask", "distortion", "date", "center"};
  EXPECT_EQ(closestName("distorsion", keys), "distortion");
  EXPECT_EQ(closestName("masque", keys), "mask");
  EXPECT_EQ(closestName("Centre", keys), "center");
  EXPECT_EQ(closestName("colour", keys), "");
  EXPECT_EQ(closestName("", keys), "");
}

// A warning met on every view (K capped by the slots) is printed once per run; a different
// message still is.
TEST(Log, EachDistinctWarningIsPrintedOnce) {
  const log::Level before = log::level();
  log::setLevel(log::Level::Warn);
  std::ostringstream captured;
  std::streambuf* old = std::cerr.rdbuf(captured.rdbuf());
  Diagnostics diag;
  for (int view = 0; view < 3; ++view) diag.warn("log test: the same cause on every view");
  diag.warn("log test: another cause");
  diag.error("log test: the same cause on every view");  // an error is not the warning
  std::cerr.rdbuf(old);
  log::setLevel(before);
  EXPECT_EQ(captured.str(),
            "warning: log test: the same cause on every view\n"
            "warning: log test: another cause\n"
            "error: log test: the same cause on every view\n");
  EXPECT_EQ(diag.warnings.size(), 4u);  // the record keeps every occurrence
}

}  // namespace
}  // namespace hv
