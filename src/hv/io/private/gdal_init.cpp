#include "hv/io/private/gdal_init.h"

#include <gdal.h>

#include <mutex>

namespace hv::gdal {

void ensureRegistered() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

std::string lastError(const std::string& fallback) {
  const char* message = CPLGetLastErrorMsg();
  return (message && *message) ? std::string(message) : fallback;
}

}  // namespace hv::gdal
