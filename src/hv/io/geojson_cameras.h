// Photographs' cameras from a GeoJSON page of camera points (docs/services.md, "In the browser"):
// a page of a WFS 2.0 GetFeature answered as GeoJSON, or of an OGC API – Features `items`, over a
// layer in the 2022 layout that the native reader takes through OGR (docs/formats.md, "Cameras as
// an OGR point layer"; hv/io/native/camera_catalog.h, readOgrCameras): a 3D Point at the camera
// centre, the rest as properties. Portable (the browser build reads what its page fetched; no
// GDAL), decoded by the same per-feature code as the native reader (hv/io/camera_properties.h),
// coordinates taken as they are (the page asks the service for the scene's CRS).
#pragma once

#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <cstddef>
#include <string>
#include <vector>

namespace hv {

struct GeoJsonCameraPage {
  std::vector<Photo> photos;  // in the page's order; image and mask paths as the layer has them
  std::size_t features = 0;   // in the page, kept or not
  std::string next;           // the `next` link's href (OGC API), empty: none
};

// One page. A feature whose camera cannot be read is left out with an error naming `name` (the
// page's URL), the feature (its "id", else its index in the page), the camera and the field, as
// the native reader words it: "URL: feature cameras.3 (camera 'p3'): focal_x: expected a number,
// got \"a\" (camera skipped)". Throws InputError naming `name` when the text is not JSON or not a
// FeatureCollection.
GeoJsonCameraPage parseGeoJsonCameras(const std::string& text, const std::string& name, Diagnostics& diag);

}  // namespace hv
