// Streaming: photographs decoded into slice images (makeSliceImage) off the
// render thread, under a memory cap. GL-free: the renderer uploads what poll()/wait() hand back.
//
// - Requests are queued by priority (lower value first: the renderer passes the camera's distance
//   to the view, so the nearest images arrive first; ties in request order) and deduplicated: a
//   re-request of a queued photo only updates its priority.
// - workerThreads > 0: that many threads decode. workerThreads == 0 (the browser build, no
//   threads): nothing happens in the background; poll() decodes a bounded amount of work on the
//   caller's thread and wait() decodes what it waits for.
// - Memory cap: what the loader holds (results not yet collected plus, for every decode in
//   progress, an upper bound of everything it allocates: the file, the library's decode buffers,
//   the full-size image and mask, their resized copies, the resize scratch and the slice) never
//   exceeds `memoryCapBytes`. The bound is computed from the file headers before a decode starts;
//   a decode that does not fit waits (for poll()/wait() to collect results or for other decodes to
//   finish), and a photo whose bound alone exceeds the cap gets an error result. The queue itself
//   (a camera and two paths per request) is not counted.
// - Errors never stop the loader: a missing, undecodable or mis-sized image or mask becomes an
//   error result naming the camera and the field ("camera 'ID': image: ..." / "camera 'ID': mask
//   ..."), so the renderer can report and skip that photo.
// - Jobs start in priority order: a job whose bound does not fit keeps the head of the queue and
//   everything behind it waits, so a stream of small far images never starves a large near one.
//
// Member functions are meant to be called from one thread (the render thread); they lock, so
// another thread may also call them. The destructor discards pending work and joins the workers,
// waiting at most for the decodes in progress.
//
// A photograph or mask named by an http(s):// URL (docs/services.md) is fetched whole when its job
// is probed (through the remote reader hv/util/input_file.h installs: the response cache, GDAL's
// HTTP client) and decoded from memory; the reservation counts it as the file. Fetched responses
// of probed jobs still waiting for memory are outside the cap: at most a window of (threads + 1)
// jobs is probed ahead.
//
// Previews: a photograph whose server offers it at several sizes (hv/util/image_sizes.h, a IIIF
// image service) is fetched small first: its preview job gives a result marked `preview` (the
// slice made from the small image, scaled up: the same projection), and then the same photo is
// queued again for the image at the width its slice needs (never larger than the server's full
// size), whose result replaces the preview. Every queued preview goes before every such second
// job (then by priority). A photo waited for (wait()) skips the preview it has not started, and
// its second job is waited for too; a request with `preview` false (batch frames) asks for the
// full image only. A preview that fails is
// dropped and the full image asked instead (its error, if any, is the one reported). A local file
// has no preview: stb_image has no reduced-scale decode, so a preview would cost the full decode
// it is meant to avoid.
#pragma once

#include "hv/ibr/slice_image.h"
#include "hv/scene/scene.h"

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

namespace hv::ibr {

struct LoadResult {
  int photo = -1;
  Image8 slice;       // premultiplied RGBA, slice.width x slice.height (sliceLayout's layout)
  std::string error;  // non-empty: the photo cannot be loaded, `slice` is empty
  // The slice of a preview: the full image of this photo follows (the photo stays pending).
  bool preview = false;
  int imageWidth = 0, imageHeight = 0;  // the size of the image the slice was made from
  bool ok() const { return error.empty(); }
};

struct LoadRequest {
  int photo = -1;
  const Photo* source = nullptr;  // copied by request(): need not outlive it
  double priority = 0.0;
  bool preview = true;  // a preview first where the server offers one (false: batch frames)
};

class ImageLoader {
 public:
  // `useMasks` false ignores Photo::maskPath (the renderer's --no-masks). Throws
  // std::invalid_argument for an empty slice size, negative thread count or zero cap.
  ImageLoader(SliceSize slice, int workerThreads, std::size_t memoryCapBytes, bool useMasks = true);
  ~ImageLoader();
  ImageLoader(const ImageLoader&) = delete;
  ImageLoader& operator=(const ImageLoader&) = delete;

  // Queues a decode of `photo` (the id the results carry; the renderer's index into
  // Scene::photos). Returns true when a new decode was queued; false when the photo is already
  // queued (its priority is updated), being decoded, or decoded and not yet collected.
  // `preview` false: the full image only (a batch frame), even where a preview is offered.
  bool request(int photo, const Photo& source, double priority, bool preview = true);
  // The same for many photos under one lock: a frame's requests are queued together, so the
  // workers see them all and start them in priority order.
  void request(const std::vector<LoadRequest>& requests);
  // Drops a queued decode, discards the result of one in progress, or frees an uncollected result.
  // False when the loader had nothing for the photo.
  bool cancel(int photo);
  void cancelAll();

  // Never blocks on decodes. Returns the results finished so far (in completion order) and hands
  // their memory to the caller. With no worker threads it first decodes, on this thread, the
  // queue's head (when it fits the cap) and then more while `inlineBudget` has not elapsed.
  std::vector<LoadResult> poll(std::chrono::microseconds inlineBudget = std::chrono::microseconds(0));
  // Blocks until none of `photos` is queued or being decoded (batch frames: render and eval wait for
  // full residency). The listed photos move ahead of the rest of the queue. Every result that
  // becomes ready meanwhile, listed or not, is handed to `sink` as it arrives, so the cap holds
  // however many photos are waited for. Photos the loader does not hold are ignored.
  void wait(const std::vector<int>& photos, const std::function<void(LoadResult&&)>& sink);

  // Queued plus in progress plus uncollected results.
  std::size_t pending() const;
  bool isPending(int photo) const;
  // The bytes a decode of `source` reserves while it runs (its slice included), from the file
  // headers. Throws InputError naming the camera and field when a file cannot be probed.
  std::size_t jobBytes(const Photo& source) const;
  std::size_t bytesInUse() const;
  std::size_t peakBytes() const;
  std::size_t memoryCap() const { return cap_; }
  SliceSize sliceSize() const { return slice_; }
  int workerThreads() const { return int(workers_.size()); }

 private:
  struct FileInfo {
    // An http(s):// image or mask (docs/services.md): fetched whole by the probe (HTTP has no cheap
    // header read) and kept for the decode; null for a local file, read again by the decode.
    std::shared_ptr<const std::vector<std::uint8_t>> fetched;
    std::uintmax_t fileBytes = 0;
    int width = 0, height = 0, channels = 0;
    bool is16 = false;
  };
  struct Probe {
    std::size_t bytes = 0;  // reservation while decoding, slice included
    FileInfo image;
    std::optional<FileInfo> mask;
    std::string error;  // the photo cannot be loaded: no decode, an error result
  };
  struct Job {
    Camera camera;
    std::string imagePath, maskPath;
    double priority = 0.0;
    bool urgent = false;  // waited for: ahead of every other job
    // A preview job (imagePath the preview) is followed by a job of `fullPath`; a job that follows
    // one (`second`) goes after every preview.
    bool preview = false, second = false;
    std::string fullPath;
    std::uint64_t seq = 0;
    bool probing = false;
    std::optional<Probe> probe;
  };
  struct Key {
    bool notUrgent;
    bool second;
    double priority;
    std::uint64_t seq;
    int photo;
    auto operator<=>(const Key&) const = default;
  };
  // What one unit of work did: nothing queued; the queue's head is being probed by another thread
  // and nothing else needs probing; the head does not fit the cap; a header was probed; a job ran.
  enum class Step { Empty, Busy, Blocked, Probed, Ran };
  enum class Requested { Unchanged, Reordered, Added };

  static Key keyOf(int photo, const Job& job) { return {!job.urgent, job.second, job.priority, job.seq, photo}; }
  void skipPreview(Job& job) const;
  Requested requestLocked(int photo, const Photo& source, double priority, bool preview);
  Step step(std::unique_lock<std::mutex>& lock);
  void workerLoop();
  Probe probe(const Job& job) const;
  LoadResult decode(int photo, const Job& job, const Probe& probe) const;
  std::vector<LoadResult> collectLocked();
  bool finishedLocked(const std::vector<int>& photos) const;

  const SliceSize slice_;
  const std::size_t cap_;
  const std::size_t sliceBytes_;
  const bool useMasks_;

  mutable std::mutex mutex_;
  std::condition_variable workCv_;  // workers: queue, memory or probe state changed, or stop
  std::condition_variable doneCv_;  // wait(): a result is ready
  bool stop_ = false;
  std::uint64_t nextSeq_ = 0;
  std::unordered_map<int, Job> queued_;
  std::set<Key> order_;
  std::unordered_map<int, bool> running_;  // photo -> cancelled while running
  std::deque<LoadResult> ready_;
  std::size_t bytesInUse_ = 0, peakBytes_ = 0;
  std::vector<std::thread> workers_;
};

}  // namespace hv::ibr
