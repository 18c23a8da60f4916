// Linked with the whole portable library (every object, not only those referenced) and nothing
// native: if any portable source reaches GDAL, GEOS, Embree, Assimp, libpng or EGL, this
// executable does not link. Run, it only says so.
#include <cstdio>

int main() {
  std::puts("the portable core links without native libraries");
  return 0;
}
