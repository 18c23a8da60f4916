// What the browser build needs of the service scenes beyond the portable readers (docs/services.md,
// "In the browser"): photographs by URL, which the page fetches and puts into the in-memory file
// system where the image loader's remote reader finds them, and the requests a camera makes of a
// IIIF image service (hv/io/iiif.h's size rules, as the native loader makes them).
#pragma once

#include "hv/scene/scene.h"

#include <string>

namespace hv::web {

// Where the page puts the bytes of `url`: `root` + "remote/" + the URL percent-encoded as
// JavaScript's encodeURIComponent does (letters, digits and -_.!~*'() kept).
std::string remoteFilePath(const std::string& root, const std::string& url);

// Installs the remote reader (hv/util/input_file.h) that reads an http(s) URL from
// remoteFilePath(root, url), refusing, with a message naming the URL, one the page has not put.
void installPageRemoteReader(const std::string& root);

// The requests for photograph `photo` from the IIIF image service whose info.json is `infoText`,
// read from `url`: {"full": {"url", "width", "height"}, "preview": {...} or null} (the preview:
// fitted in 256 x 256, or in a quarter of the camera's longer side when smaller; none when it
// would not be smaller than the full request), or {"error": "..."} naming the URL when the
// description cannot be read or its image has another aspect ratio than the camera's. The photo
// is then read from the full request, its preview registered (hv/util/image_sizes.h): the image
// loader decodes the preview first, then the full image, as natively; the page puts both before
// the photograph joins (photoArrived).
std::string iiifPlan(Photo& photo, const std::string& infoText, const std::string& url);

}  // namespace hv::web
