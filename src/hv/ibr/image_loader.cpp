#include "hv/ibr/image_loader.h"

#include "hv/image/image_header.h"
#include "hv/util/diagnostics.h"
#include "hv/util/image_sizes.h"
#include "hv/util/input_file.h"

#include <stb_image.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>

namespace hv::ibr {

namespace {

using FilePtr = std::unique_ptr<FILE, int (*)(FILE*)>;

FilePtr openFile(const std::string& path) {
  // A FIFO or device named as a photograph would block the open or never end.
  if (const std::string reason = notRegularFileReason(path); !reason.empty()) throw InputError(path + ": " + reason);
  FilePtr f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw InputError(path + ": cannot open file");  // decodeImage's wording
  return f;
}

// `head`: the first bytes of the file, for the header probe (hv/image/image.h undecodableReason).
std::string decodeFailure(const std::string& path, const std::vector<std::uint8_t>& head) {
  if (const std::string why = undecodableReason(head.data(), head.size()); !why.empty())
    return path + ": cannot decode image: " + why;
  const char* reason = stbi_failure_reason();
  return path + ": cannot decode image (expected JPEG or PNG): " + (reason ? reason : "unknown error");
}

std::string cameraName(const Camera& camera) { return "camera '" + camera.id + "'"; }

// The width of a camera's image in its slice, as makeSliceImage computes it (rounded up).
int sliceContentWidth(const Camera& camera, SliceSize slice) {
  const SliceLayout layout = sliceLayout(camera, slice, 0);
  return std::clamp(int(std::ceil(layout.uvScale.x * slice.width * camera.width - 1e-6)), 1, slice.width);
}

// Bytes a decode of one file allocates at its peak (an upper bound, from stb_image 2.x's
// allocation pattern): our copy of the file; stb's (PNG: the IDAT stream, grown by doubling, so up
// to twice the file; the inflated rows; the unfiltered image; channel and 16-to-8-bit conversions;
// JPEG: one plane per component padded to whole 16-pixel MCUs, 2-byte coefficients when
// progressive, the interleaved output) -- at most four 4-channel planes at the file's sample size;
// and the Image8 decodeImage copies out while stb's buffer is still alive.
std::size_t decodeBytes(std::uintmax_t fileBytes, int width, int height, int channels, bool is16) {
  const std::size_t padded = std::size_t(width + 16) * std::size_t(height + 16);
  const std::size_t stb = 4 * padded * 4 * (is16 ? 2 : 1);
  return 3 * std::size_t(fileBytes) + stb + std::size_t(width) * std::size_t(height) * std::size_t(channels);
}

// Scratch stb_image_resize allocates for srcW x srcH -> dstW x dstH (stbir__calculate_memory with
// the default Mitchell / Catmull-Rom filters, support 2): per axis, one contributor (8 bytes) and
// four float coefficients per input pixel plus margins when shrinking (per output pixel when
// enlarging); a float decode row of the input, a float row of the output, and a ring of output
// rows as tall as the vertical filter (4 input rows per output row when shrinking) plus one.
std::size_t resizeScratchBytes(int srcW, int srcH, int dstW, int dstH, int channels) {
  const auto filterWidth = [](int in, int out) {
    return std::size_t(std::ceil(4.0 * std::max(1.0, double(in) / out))) + 1;
  };
  const std::size_t fx = filterWidth(srcW, dstW), fy = filterWidth(srcH, dstH);
  const std::size_t tables = 24 * (std::size_t(srcW) + dstW + 2 * fx) + 24 * (std::size_t(srcH) + dstH + 2 * fy);
  const std::size_t c = std::size_t(channels);
  const std::size_t rows = 4 * c * (std::size_t(srcW) + 2 * fx + 2 * std::size_t(dstW) + std::size_t(dstW) * (fy + 1));
  return tables + rows;
}

}  // namespace

ImageLoader::ImageLoader(SliceSize slice, int workerThreads, std::size_t memoryCapBytes, bool useMasks)
    : slice_(slice),
      cap_(memoryCapBytes),
      sliceBytes_(std::size_t(std::max(slice.width, 0)) * std::size_t(std::max(slice.height, 0)) * 4),
      useMasks_(useMasks) {
  if (slice.width <= 0 || slice.height <= 0)
    throw std::invalid_argument("image loader: empty slice size " + std::to_string(slice.width) + "x" +
                                std::to_string(slice.height));
  if (workerThreads < 0) throw std::invalid_argument("image loader: negative worker thread count");
  if (memoryCapBytes == 0) throw std::invalid_argument("image loader: zero memory cap");
  try {
    for (int i = 0; i < workerThreads; ++i) workers_.emplace_back([this] { workerLoop(); });
  } catch (...) {
    // Threads already started must be joined before the exception leaves the constructor.
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    workCv_.notify_all();
    for (auto& t : workers_) t.join();
    throw;
  }
}

ImageLoader::~ImageLoader() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  workCv_.notify_all();
  doneCv_.notify_all();
  for (auto& t : workers_) t.join();
}

ImageLoader::Requested ImageLoader::requestLocked(int photo, const Photo& source, double priority, bool preview) {
  // A NaN would break the queue's ordering; such a photo goes last.
  if (std::isnan(priority)) priority = std::numeric_limits<double>::infinity();
  if (auto it = running_.find(photo); it != running_.end()) {
    it->second = false;  // cancelled while decoding, wanted again: keep the result
    return Requested::Unchanged;
  }
  if (std::any_of(ready_.begin(), ready_.end(), [&](const LoadResult& r) { return r.photo == photo; }))
    return Requested::Unchanged;
  if (auto it = queued_.find(photo); it != queued_.end()) {
    if (it->second.priority == priority) return Requested::Unchanged;
    order_.erase(keyOf(photo, it->second));
    it->second.priority = priority;
    order_.insert(keyOf(photo, it->second));
    return Requested::Reordered;
  }
  Job job;
  job.camera = source.camera;
  job.imagePath = source.imagePath;
  // A photograph its server offers at several sizes: the preview first when it is smaller than the
  // image at the width of the slice, then that image.
  if (const auto sizes = isHttpUrl(source.imagePath) ? imageSizes(source.imagePath) : nullptr;
      sizes && sizes->atWidth && job.camera.width > 0 && job.camera.height > 0) {
    const SizedImageUrl full = sizes->atWidth(sliceContentWidth(job.camera, slice_));
    job.fullPath = full.url;
    job.preview = preview && !sizes->preview.url.empty() && sizes->preview.width < full.width;
    job.imagePath = job.preview ? sizes->preview.url : full.url;
  }
  if (useMasks_) job.maskPath = source.maskPath;
  job.priority = priority;
  job.seq = nextSeq_++;
  order_.insert(keyOf(photo, job));
  queued_.emplace(photo, std::move(job));
  return Requested::Added;
}

void ImageLoader::skipPreview(Job& job) const {
  if (!job.preview || job.probing) return;
  job.preview = false;
  job.imagePath = job.fullPath;
  job.probe.reset();
}

bool ImageLoader::request(int photo, const Photo& source, double priority, bool preview) {
  Requested what;
  {
    std::lock_guard lock(mutex_);
    what = requestLocked(photo, source, priority, preview);
  }
  // Wake the workers only for a change of the queue (a reordering may change its head): the
  // renderer re-requests what it still misses every frame.
  if (what != Requested::Unchanged) workCv_.notify_all();
  return what == Requested::Added;
}

void ImageLoader::request(const std::vector<LoadRequest>& requests) {
  bool changed = false;
  {
    std::lock_guard lock(mutex_);
    for (const LoadRequest& r : requests) {
      if (!r.source) throw std::invalid_argument("image loader: request without a photo");
      changed |= requestLocked(r.photo, *r.source, r.priority, r.preview) != Requested::Unchanged;
    }
  }
  if (changed) workCv_.notify_all();
}

bool ImageLoader::cancel(int photo) {
  bool found = false;
  {
    std::lock_guard lock(mutex_);
    if (auto it = queued_.find(photo); it != queued_.end()) {
      order_.erase(keyOf(photo, it->second));
      queued_.erase(it);  // a probe in progress notices through the sequence number
      found = true;
    } else if (auto rt = running_.find(photo); rt != running_.end()) {
      rt->second = true;
      found = true;
    } else if (auto r =
                   std::find_if(ready_.begin(), ready_.end(), [&](const LoadResult& x) { return x.photo == photo; });
               r != ready_.end()) {
      if (r->ok()) bytesInUse_ -= sliceBytes_;
      ready_.erase(r);
      found = true;
    }
  }
  workCv_.notify_all();  // memory may have been freed
  doneCv_.notify_all();  // a wait() for this photo may be over
  return found;
}

void ImageLoader::cancelAll() {
  {
    std::lock_guard lock(mutex_);
    queued_.clear();
    order_.clear();
    for (auto& [photo, cancelled] : running_) cancelled = true;
    for (const LoadResult& r : ready_)
      if (r.ok()) bytesInUse_ -= sliceBytes_;
    ready_.clear();
  }
  workCv_.notify_all();
  doneCv_.notify_all();
}

ImageLoader::Probe ImageLoader::probe(const Job& job) const {
  Probe p;
  const std::string who = cameraName(job.camera);
  const auto probeFile = [](const std::string& path) {
    if (isHttpUrl(path)) {
      // The remote reader (installed by the native build) names the URL and the HTTP status.
      auto bytes = std::make_shared<const std::vector<std::uint8_t>>(
          readInputBytes(path, std::min<std::uint64_t>(kMaxImageBytes, INT_MAX), "", RemoteCache::Yes));
      FileInfo info;
      info.fileBytes = bytes->size();
      checkImageBytes(bytes->data(), bytes->size(), path, true);
      if (!stbi_info_from_memory(bytes->data(), int(bytes->size()), &info.width, &info.height, &info.channels))
        throw InputError(decodeFailure(path, *bytes));
      info.is16 = stbi_is_16_bit_from_memory(bytes->data(), int(bytes->size())) != 0;
      info.fetched = std::move(bytes);
      return info;
    }
    FilePtr f = openFile(path);
    FileInfo info;
    if (std::fseek(f.get(), 0, SEEK_END) != 0) throw InputError(path + ": cannot read file");
    const long size = std::ftell(f.get());
    if (size < 0 || std::fseek(f.get(), 0, SEEK_SET) != 0) throw InputError(path + ": cannot read file");
    if (size > long(INT_MAX)) throw InputError(path + ": image file too large");
    info.fileBytes = std::uintmax_t(size);
    // stbi_info parses JPEG marker segments (Huffman tables included) up to the frame header:
    // check what it will read first (the first MiB; the decode checks the whole file).
    std::vector<std::uint8_t> head(size_t(std::min<long>(size, 1L << 20)));
    if (std::fread(head.data(), 1, head.size(), f.get()) != head.size() || std::fseek(f.get(), 0, SEEK_SET) != 0)
      throw InputError(path + ": cannot read file");
    checkImageBytes(head.data(), head.size(), path, head.size() == size_t(size));
    // Header only: stbi_info reads the few bytes up to the size fields and restores the position.
    if (!stbi_info_from_file(f.get(), &info.width, &info.height, &info.channels))
      throw InputError(decodeFailure(path, head));
    info.is16 = stbi_is_16_bit_from_file(f.get()) != 0;
    return info;
  };
  const char* field = "image";
  try {
    if (job.camera.width <= 0 || job.camera.height <= 0) throw InputError("the camera has no image size");
    p.image = probeFile(job.imagePath);
    if (p.image.fetched) countImageFetch(job.preview, p.image.fileBytes);
    if (!job.maskPath.empty()) {
      field = "mask";
      p.mask = probeFile(job.maskPath);
      // From the headers, before anything is decoded: a mask of another aspect ratio than the
      // camera's image cannot be scaled onto it (makeSliceImage), so the photograph is left out.
      const double aspect = double(job.camera.width) / job.camera.height;
      if (p.mask->height <= 0 || std::abs(double(p.mask->width) / p.mask->height - aspect) > 0.01 * aspect)
        throw InputError(job.maskPath + ": the mask is " + std::to_string(p.mask->width) + "x" +
                         std::to_string(p.mask->height) + " pixels, expected the camera's " +
                         std::to_string(job.camera.width) + "x" + std::to_string(job.camera.height) +
                         " or the same aspect ratio (photograph left out)");
    }
  } catch (const std::exception& e) {
    p.error = inputMessage(who, field, e.what());
    return p;
  }
  // The slice's content size, as makeSliceImage computes it (rounded up: an upper bound).
  const SliceLayout layout = sliceLayout(job.camera, slice_, 0);
  const int w = std::clamp(int(std::ceil(layout.uvScale.x * slice_.width * job.camera.width - 1e-6)), 1, slice_.width);
  const int h =
      std::clamp(int(std::ceil(layout.uvScale.y * slice_.height * job.camera.height - 1e-6)), 1, slice_.height);
  const FileInfo& im = p.image;
  // Everything is summed although the phases (decode image, decode mask, build the slice) overlap
  // only partly: simpler to check, and it errs on the safe side.
  p.bytes = sliceBytes_ + decodeBytes(im.fileBytes, im.width, im.height, im.channels, im.is16) +
            std::size_t(w) * h * std::size_t(im.channels) + resizeScratchBytes(im.width, im.height, w, h, im.channels);
  if (p.mask) {
    const FileInfo& m = *p.mask;
    p.bytes += decodeBytes(m.fileBytes, m.width, m.height, 1, m.is16) + std::size_t(w) * h +
               resizeScratchBytes(m.width, m.height, w, h, 1);
  }
  return p;
}

LoadResult ImageLoader::decode(int photo, const Job& job, const Probe& probe) const {
  LoadResult r;
  r.photo = photo;
  const std::string who = cameraName(job.camera);
  // Reads exactly the probed file and checks its header again: a file replaced since the probe
  // could need more memory than was reserved, so it is refused rather than decoded.
  const auto read = [](const std::string& path, const FileInfo& info, int wantChannels) {
    if (info.fetched) return decodeImage(info.fetched->data(), info.fetched->size(), path, wantChannels);
    FilePtr f = openFile(path);
    std::vector<std::uint8_t> bytes(std::size_t(info.fileBytes));
    const bool complete =
        std::fread(bytes.data(), 1, bytes.size(), f.get()) == bytes.size() && std::fgetc(f.get()) == EOF;
    int w = 0, h = 0, n = 0;
    if (!complete || !stbi_info_from_memory(bytes.data(), int(bytes.size()), &w, &h, &n) || w != info.width ||
        h != info.height || n != info.channels ||
        (stbi_is_16_bit_from_memory(bytes.data(), int(bytes.size())) != 0) != info.is16)
      throw InputError(path + ": the file changed while it was being loaded");
    return decodeImage(bytes.data(), bytes.size(), path, wantChannels);
  };
  const char* field = "image";
  try {
    const Image8 colour = read(job.imagePath, probe.image, 0);
    Image8 mask;
    if (probe.mask) {
      field = "mask";
      mask = read(job.maskPath, *probe.mask, 1);
    }
    field = nullptr;
    // makeSliceImage's own errors already read "camera 'ID': image is ..." / "...: mask is ...".
    r.slice = makeSliceImage(job.camera, colour, mask, slice_, who);
    r.imageWidth = colour.width;
    r.imageHeight = colour.height;
  } catch (const InputError& e) {
    r.error = field ? inputMessage(who, field, e.what()) : e.what();
  } catch (const std::exception& e) {  // out of memory, a resize failure: still only this photo
    r.error = inputMessage(who, field ? field : "image", e.what());
  } catch (...) {
    r.error = inputMessage(who, field ? field : "image", "unknown error");
  }
  if (!r.ok()) r.slice = Image8();
  return r;
}

ImageLoader::Step ImageLoader::step(std::unique_lock<std::mutex>& lock) {
  if (order_.empty()) return Step::Empty;
  const int head = order_.begin()->photo;
  Job& headJob = queued_.at(head);
  if (!headJob.probe) {
    // Probe the head, or while another thread probes it, the next unprobed job of a short window
    // (as many jobs as threads could start), so the headers are known when memory frees up.
    const std::size_t window = std::max<std::size_t>(1, workers_.size()) + 1;
    std::size_t k = 0;
    for (auto it = order_.begin(); it != order_.end() && k < window; ++it, ++k) {
      Job& job = queued_.at(it->photo);
      if (job.probe || job.probing) continue;
      job.probing = true;
      const int photo = it->photo;
      const Job copy = job;
      lock.unlock();
      Probe p = probe(copy);
      lock.lock();
      // Cancelled (and perhaps requested again as a new job) meanwhile: the probe is not its.
      if (auto jt = queued_.find(photo); jt != queued_.end() && jt->second.seq == copy.seq) {
        jt->second.probing = false;
        jt->second.probe = std::move(p);
      }
      workCv_.notify_all();
      return Step::Probed;
    }
    return Step::Busy;
  }

  // The head is probed: start it when it fits, else everything waits behind it (priority order).
  const Probe& pr = *headJob.probe;
  std::string error = pr.error;
  if (error.empty() && pr.bytes > cap_)
    error = inputMessage(cameraName(headJob.camera), "image",
                         std::to_string(pr.image.width) + "x" + std::to_string(pr.image.height) + " needs " +
                             std::to_string(pr.bytes) + " bytes to load, more than the image loader's memory cap (" +
                             std::to_string(cap_) + " bytes)");
  const std::size_t reserve = error.empty() ? pr.bytes : 0;
  if (bytesInUse_ + reserve > cap_) return Step::Blocked;
  Job job = std::move(headJob);
  queued_.erase(head);
  order_.erase(order_.begin());
  running_[head] = false;
  bytesInUse_ += reserve;
  peakBytes_ = std::max(peakBytes_, bytesInUse_);
  lock.unlock();

  LoadResult r;
  if (error.empty()) {
    r = decode(head, job, *job.probe);
  } else {
    r.photo = head;
    r.error = std::move(error);
  }

  lock.lock();
  const auto rt = running_.find(head);
  const bool cancelled = rt->second;
  running_.erase(rt);
  if (cancelled) r = LoadResult();  // freed before it stops being counted
  bytesInUse_ -= reserve;
  bool deliver = !cancelled;
  if (!cancelled && job.preview) {
    // The image at the slice's width follows (waited for when the preview was); a preview that
    // failed is dropped: the full image says whether the photo can be loaded.
    Job next;
    next.camera = std::move(job.camera);
    next.imagePath = std::move(job.fullPath);
    next.maskPath = std::move(job.maskPath);
    next.priority = job.priority;
    next.urgent = job.urgent;
    next.second = true;
    next.seq = nextSeq_++;
    order_.insert(keyOf(head, next));
    queued_.emplace(head, std::move(next));
    r.preview = r.ok();
    deliver = r.ok();
  }
  if (deliver) {
    if (r.ok()) bytesInUse_ += sliceBytes_;  // part of the reservation just released: no new peak
    ready_.push_back(std::move(r));
  }
  workCv_.notify_all();
  doneCv_.notify_all();
  return Step::Ran;
}

void ImageLoader::workerLoop() {
  std::unique_lock lock(mutex_);
  while (!stop_) {
    const Step s = step(lock);
    // Empty, Busy and Blocked return without unlocking, so no notification can fall between the
    // stop_ check and this wait.
    if (s == Step::Empty || s == Step::Busy || s == Step::Blocked) workCv_.wait(lock);
  }
}

std::vector<LoadResult> ImageLoader::collectLocked() {
  std::vector<LoadResult> out;
  out.reserve(ready_.size());
  for (LoadResult& r : ready_) {
    if (r.ok()) bytesInUse_ -= sliceBytes_;
    out.push_back(std::move(r));
  }
  ready_.clear();
  if (!out.empty()) workCv_.notify_all();
  return out;
}

bool ImageLoader::finishedLocked(const std::vector<int>& photos) const {
  return std::none_of(photos.begin(), photos.end(),
                      [&](int p) { return queued_.count(p) > 0 || running_.count(p) > 0; });
}

std::vector<LoadResult> ImageLoader::poll(std::chrono::microseconds inlineBudget) {
  std::unique_lock lock(mutex_);
  if (workers_.empty()) {
    const auto start = std::chrono::steady_clock::now();
    for (;;) {
      const Step s = step(lock);
      if (s == Step::Probed) continue;
      if (s != Step::Ran || std::chrono::steady_clock::now() - start >= inlineBudget) break;
    }
  }
  return collectLocked();
}

void ImageLoader::wait(const std::vector<int>& photos, const std::function<void(LoadResult&&)>& sink) {
  std::unique_lock lock(mutex_);
  for (int p : photos) {
    auto it = queued_.find(p);
    if (it == queued_.end() || it->second.urgent) continue;
    order_.erase(keyOf(p, it->second));
    it->second.urgent = true;
    skipPreview(it->second);  // a batch frame shows the full image: no preview unless one started
    order_.insert(keyOf(p, it->second));
  }
  workCv_.notify_all();
  for (;;) {
    std::vector<LoadResult> batch = collectLocked();
    if (!batch.empty()) {
      lock.unlock();  // the sink may upload, or request more
      for (LoadResult& r : batch) sink(std::move(r));
      lock.lock();
      continue;
    }
    if (finishedLocked(photos)) return;
    // Without workers the waited-for photos, now at the head, are decoded here; nothing else is
    // held (results were just collected), so the head always fits. Otherwise (workers, or another
    // thread busy with the head) sleep until a decode finishes.
    if (workers_.empty()) {
      const Step s = step(lock);
      if (s == Step::Ran || s == Step::Probed) continue;
    }
    doneCv_.wait(lock);
  }
}

std::size_t ImageLoader::pending() const {
  std::lock_guard lock(mutex_);
  return queued_.size() + running_.size() + ready_.size();
}

bool ImageLoader::isPending(int photo) const {
  std::lock_guard lock(mutex_);
  return queued_.count(photo) > 0 || running_.count(photo) > 0 ||
         std::any_of(ready_.begin(), ready_.end(), [&](const LoadResult& r) { return r.photo == photo; });
}

std::size_t ImageLoader::jobBytes(const Photo& source) const {
  Job job;
  job.camera = source.camera;
  job.imagePath = source.imagePath;
  if (useMasks_) job.maskPath = source.maskPath;
  const Probe p = probe(job);
  if (!p.error.empty()) throw InputError(p.error);
  return p.bytes;
}

std::size_t ImageLoader::bytesInUse() const {
  std::lock_guard lock(mutex_);
  return bytesInUse_;
}

std::size_t ImageLoader::peakBytes() const {
  std::lock_guard lock(mutex_);
  return peakBytes_;
}

}  // namespace hv::ibr
