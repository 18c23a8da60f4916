// A private PostgreSQL 15 + PostGIS cluster for the tests of the camera catalog, started and stopped
// through tools/catalog.sh (the same script a user runs by hand, docs/catalog.md). The script
// runs the server as an unprivileged user when the tests run as root, and watches this process:
// a test that crashes leaves no server behind.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace hv::testing {

class CatalogServer {
 public:
  // Whether the server can be made here (PostgreSQL 15's initdb installed); when not, the tests fail.
  static bool available() { return std::filesystem::exists("/usr/lib/postgresql/15/bin/initdb"); }

  // Starts the cluster; `error()` says why when `connection()` is empty afterwards.
  explicit CatalogServer(const std::string& sourceDir) : script_(sourceDir + "/tools/catalog.sh") {
    char dirTemplate[] = "/tmp/hv-catalog-test.XXXXXX";
    if (!mkdtemp(dirTemplate)) {
      error_ = "mkdtemp failed";
      return;
    }
    // tools/catalog.sh makes the folder the server's (not root's) and removes it at `down`.
    dir_ = dirTemplate;
    const std::string cmd = "HV_CATALOG_DIR='" + dir_ + "' HV_CATALOG_OWNER_PID=" + std::to_string(::getpid()) +
                            " bash '" + script_ + "' up 2>&1";
    std::string out;
    if (FILE* p = popen(cmd.c_str(), "r")) {
      char buffer[512];
      while (fgets(buffer, sizeof buffer, p)) out += buffer;
      if (pclose(p) != 0) {
        error_ = "tools/catalog.sh up failed: " + out;
        return;
      }
    }
    while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
    const std::size_t line = out.rfind('\n');
    connection_ = line == std::string::npos ? out : out.substr(line + 1);
    if (connection_.rfind("postgresql://", 0) != 0) {
      error_ = "tools/catalog.sh up printed no connection: " + out;
      connection_.clear();
    }
  }
  ~CatalogServer() {
    if (dir_.empty()) return;
    const std::string cmd = "HV_CATALOG_DIR='" + dir_ + "' bash '" + script_ + "' down >/dev/null 2>&1";
    if (std::system(cmd.c_str()) != 0) std::fprintf(stderr, "warning: %s failed\n", cmd.c_str());
  }
  CatalogServer(const CatalogServer&) = delete;
  CatalogServer& operator=(const CatalogServer&) = delete;

  const std::string& connection() const { return connection_; }
  const std::string& error() const { return error_; }

 private:
  std::string script_, dir_, connection_, error_;
};

}  // namespace hv::testing
