// `histoview check SCENE`: every source opened, every camera validated, every photograph's and
// mask's header probed (--deep: decoded), a report grouped by kind (hv/app/checks.h,
// docs/reliability.md). Exit 0: nothing would be left out; 1: something would be left out or
// refused; 2: the scene cannot be loaded.
#pragma once

#include "hv/session/checks.h"

#include <iosfwd>
#include <string>

namespace CLI {
class App;
}

namespace hv::app {

void addCheckCommand(CLI::App& app, int& exitCode);

// Loads `scenePath` and checks it. `report` receives the findings; the return value is the exit
// status. Errors that stop the load (InputError, std::filesystem::filesystem_error,
// std::bad_alloc) are written to `err` naming the file and give 2.
int runChecks(const std::string& scenePath, const CheckOptions& options, Scene& scene, CheckReport& report,
              std::ostream& err);

}  // namespace hv::app
