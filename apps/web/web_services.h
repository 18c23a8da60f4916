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
// description cannot be read or its image has another aspect ratio than the camera's. With a
// preview the photo is read from the preview first (it joins the selection with it: photoArrived
// once the page has put it), then iiifFullArrived switches it to the full request; without one,
// from the full request. The sizes are registered under the full request (hv/util/image_sizes.h),
// so that a photograph made resident again later reads the preview first, then the full image,
// as natively.
std::string iiifPlan(Photo& photo, const std::string& infoText, const std::string& url);

// The page has put the full request of `photo`'s IIIF plan: the photo is read from it from now on
// (the caller hands it to Renderer::replaceImage). False when the photo has no preview pending.
bool iiifFullArrived(Photo& photo);

}  // namespace hv::web
