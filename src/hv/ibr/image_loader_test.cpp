#include "hv/ibr/image_loader.h"

#include "hv/ibr/slot_cache.h"
#include "hv/image/native/png_write.h"
#include "hv/util/diagnostics.h"
#include "hv/util/image_sizes.h"
#include "hv/util/input_file.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <iterator>
#include <map>
#include <mutex>
#include <numeric>
#include <set>
#include <thread>

namespace hv::ibr {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

class ImageLoaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("hv_image_loader_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A w x h picture with `channels` channels whose content depends on `seed`.
  std::string writeImage(const std::string& name, int w, int h, int channels, int seed) {
    Image8 im(w, h, channels);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < channels; ++c) im.at(x, y, c) = std::uint8_t((seed * 53 + x * 29 + y * 71 + c * 97) % 256);
    const std::string path = (dir_ / name).string();
    writePng(path, im);
    return path;
  }
  // A 1-channel mask: left half kept, right half discarded.
  std::string writeMask(const std::string& name, int w, int h) {
    Image8 m(w, h, 1);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) m.at(x, y, 0) = x < w / 2 ? 255 : 0;
    const std::string path = (dir_ / name).string();
    writePng(path, m);
    return path;
  }
  static Photo photo(const std::string& id, int w, int h, const std::string& image, const std::string& mask = "") {
    Photo p;
    p.camera.id = id;
    p.camera.width = w;
    p.camera.height = h;
    p.camera.focal = {double(w), double(w)};
    p.camera.principal = {w / 2.0, h / 2.0};
    p.imagePath = image;
    p.maskPath = mask;
    return p;
  }
  static Image8 expectedSlice(const Photo& p, SliceSize s, bool masks = true) {
    const Image8 colour = readImage(p.imagePath);
    Image8 mask;
    if (masks && !p.maskPath.empty()) mask = readImage(p.maskPath, 1);
    return makeSliceImage(p.camera, colour, mask, s, p.camera.id);
  }

  fs::path dir_;
};

// Polls until `count` results arrived or 60 s passed.
std::vector<LoadResult> pollAll(ImageLoader& loader, std::size_t count) {
  std::vector<LoadResult> out;
  const auto deadline = std::chrono::steady_clock::now() + 60s;
  while (out.size() < count && std::chrono::steady_clock::now() < deadline) {
    auto batch = loader.poll(1ms);
    if (batch.empty() && loader.workerThreads() > 0) std::this_thread::sleep_for(100us);
    for (auto& r : batch) out.push_back(std::move(r));
  }
  return out;
}

TEST_F(ImageLoaderTest, ResultsEqualMakeSliceImage) {
  const SliceSize slice{16, 12};
  std::vector<Photo> photos = {
      photo("rgb-shrunk", 40, 30, writeImage("a.png", 40, 30, 3, 1)),
      photo("rgba-small", 8, 6, writeImage("b.png", 8, 6, 4, 2)),
      photo("grey-tall", 10, 30, writeImage("c.png", 10, 30, 1, 3)),
      photo("masked", 32, 24, writeImage("d.png", 32, 24, 3, 4), writeMask("d_mask.png", 64, 48)),
      photo("bigger-than-camera", 20, 15, writeImage("e.png", 80, 60, 3, 5)),  // same aspect ratio
  };
  for (int threads : {0, 1, 3}) {
    for (bool masks : {true, false}) {
      ImageLoader loader(slice, threads, 64 << 20, masks);
      for (std::size_t i = 0; i < photos.size(); ++i) EXPECT_TRUE(loader.request(int(i), photos[i], double(i)));
      const auto results = pollAll(loader, photos.size());
      ASSERT_EQ(results.size(), photos.size()) << threads << " threads";
      std::set<int> seen;
      for (const auto& r : results) {
        ASSERT_TRUE(r.ok()) << r.error;
        ASSERT_TRUE(seen.insert(r.photo).second);
        const Image8 want = expectedSlice(photos[std::size_t(r.photo)], slice, masks);
        EXPECT_EQ(r.slice.width, slice.width);
        EXPECT_EQ(r.slice.height, slice.height);
        EXPECT_EQ(r.slice.channels, 4);
        EXPECT_TRUE(r.slice.data == want.data) << photos[std::size_t(r.photo)].camera.id;
      }
      EXPECT_EQ(loader.pending(), 0u);
      EXPECT_EQ(loader.bytesInUse(), 0u);
      EXPECT_GT(loader.peakBytes(), 0u);
    }
  }
}

TEST_F(ImageLoaderTest, OneWorkerCompletesInPriorityOrder) {
  const Photo p = photo("cam", 24, 16, writeImage("a.png", 24, 16, 3, 1));
  // Nearest first; equal priorities keep the request order.
  const std::vector<double> priority = {5.0, 1.0, 9.0, 3.0, 1.0, 0.5, 7.0, 2.0, 9.0, 4.0, 0.0, 6.0};
  std::vector<int> want(priority.size());
  std::iota(want.begin(), want.end(), 0);
  std::stable_sort(want.begin(), want.end(), [&](int a, int b) { return priority[a] < priority[b]; });
  for (int round = 0; round < 3; ++round) {
    ImageLoader loader({8, 8}, 1, 64 << 20);
    std::vector<LoadRequest> batch;
    for (std::size_t i = 0; i < priority.size(); ++i) batch.push_back({int(i), &p, priority[i]});
    loader.request(batch);  // all queued before the worker can pick any
    std::vector<int> order;
    for (const auto& r : pollAll(loader, priority.size())) order.push_back(r.photo);
    EXPECT_EQ(order, want);
  }
}

TEST_F(ImageLoaderTest, ReRequestUpdatesPriorityAndDeduplicates) {
  const Photo p = photo("cam", 8, 8, writeImage("a.png", 8, 8, 3, 1));
  ImageLoader loader({8, 8}, 0, 1 << 20);
  EXPECT_TRUE(loader.request(10, p, 1.0));
  EXPECT_TRUE(loader.request(11, p, 2.0));
  EXPECT_TRUE(loader.request(12, p, 3.0));
  EXPECT_FALSE(loader.request(12, p, 0.0));  // queued already: only moves ahead
  EXPECT_FALSE(loader.request(10, p, 1.0));
  EXPECT_EQ(loader.pending(), 3u);
  std::vector<int> order;
  for (int i = 0; i < 3; ++i) {
    const auto got = loader.poll();  // no threads: exactly one decode per poll with no budget
    ASSERT_EQ(got.size(), 1u);
    order.push_back(got[0].photo);
  }
  EXPECT_EQ(order, (std::vector<int>{12, 10, 11}));
  EXPECT_TRUE(loader.poll().empty());
  // A NaN priority (a degenerate distance) goes last instead of corrupting the queue.
  loader.request(20, p, std::nan(""));
  loader.request(21, p, 5.0);
  EXPECT_EQ(loader.poll().at(0).photo, 21);
  EXPECT_EQ(loader.poll().at(0).photo, 20);
  // Collected: a new request decodes again (the renderer evicted it and needs it back).
  EXPECT_TRUE(loader.request(12, p, 0.0));
  EXPECT_EQ(loader.poll().size(), 1u);
}

TEST_F(ImageLoaderTest, CancelDropsQueuedAndUncollectedWork) {
  const Photo p = photo("cam", 8, 8, writeImage("a.png", 8, 8, 3, 1));
  {
    ImageLoader loader({8, 8}, 0, 1 << 20);
    for (int i = 0; i < 4; ++i) loader.request(i, p, double(i));
    EXPECT_TRUE(loader.cancel(1));
    EXPECT_FALSE(loader.cancel(1));
    EXPECT_FALSE(loader.cancel(99));
    EXPECT_FALSE(loader.isPending(1));
    std::vector<int> got;
    for (const auto& r : loader.poll(1s)) got.push_back(r.photo);
    EXPECT_EQ(got, (std::vector<int>{0, 2, 3}));
    for (int i = 0; i < 4; ++i) loader.request(i, p, double(i));
    loader.cancelAll();
    EXPECT_EQ(loader.pending(), 0u);
    EXPECT_TRUE(loader.poll(1s).empty());
  }
  {
    // An uncollected result: cancel frees its memory at once.
    ImageLoader loader({8, 8}, 1, 1 << 20);
    loader.request(5, p, 0.0);
    const auto deadline = std::chrono::steady_clock::now() + 30s;
    while (loader.bytesInUse() != 8u * 8u * 4u && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(100us);  // decoding reserves more than the slice: this is "ready"
    ASSERT_EQ(loader.bytesInUse(), 8u * 8u * 4u);
    EXPECT_TRUE(loader.isPending(5));
    EXPECT_TRUE(loader.cancel(5));
    EXPECT_EQ(loader.bytesInUse(), 0u);
    EXPECT_TRUE(loader.poll().empty());
    EXPECT_EQ(loader.pending(), 0u);
  }
}

TEST_F(ImageLoaderTest, CancelWhileDecodingDiscardsTheResult) {
  // A photo large enough that its decode is still running when cancel() comes (whatever the
  // timing, the outcome checked is the same: cancelled means never delivered, re-requested means
  // delivered exactly once).
  const Photo big = photo("big", 1200, 900, writeImage("big.png", 1200, 900, 3, 1));
  ImageLoader loader({64, 48}, 1, 256 << 20);
  const std::size_t sliceBytes = 64 * 48 * 4;
  const auto waitRunning = [&] {
    const auto deadline = std::chrono::steady_clock::now() + 30s;
    while (loader.bytesInUse() <= sliceBytes && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
  };
  loader.request(1, big, 0.0);
  waitRunning();
  EXPECT_TRUE(loader.cancel(1));
  const auto deadline = std::chrono::steady_clock::now() + 30s;
  while (loader.pending() > 0 && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(1ms);
  EXPECT_EQ(loader.pending(), 0u);
  EXPECT_TRUE(loader.poll().empty());
  EXPECT_EQ(loader.bytesInUse(), 0u);

  loader.request(2, big, 0.0);
  waitRunning();
  EXPECT_TRUE(loader.cancel(2));
  loader.request(2, big, 0.0);  // wanted again before the decode ended: its result is kept
  std::vector<int> got;
  loader.wait({2}, [&](LoadResult&& r) { got.push_back(r.photo); });
  EXPECT_EQ(got, (std::vector<int>{2}));
  EXPECT_TRUE(loader.poll().empty());
}

TEST_F(ImageLoaderTest, ZeroThreadsWorkThroughPollAndWait) {
  const SliceSize slice{8, 8};
  std::vector<Photo> photos;
  for (int i = 0; i < 10; ++i)
    photos.push_back(photo("cam" + std::to_string(i), 8, 8, writeImage("p" + std::to_string(i) + ".png", 8, 8, 3, i)));
  ImageLoader loader(slice, 0, 1 << 20);
  EXPECT_EQ(loader.workerThreads(), 0);
  for (int i = 0; i < 10; ++i) loader.request(i, photos[std::size_t(i)], double(i));
  // Nothing happens between calls: no threads.
  std::this_thread::sleep_for(5ms);
  EXPECT_EQ(loader.bytesInUse(), 0u);
  EXPECT_EQ(loader.peakBytes(), 0u);
  auto first = loader.poll();
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0].photo, 0);
  // wait() decodes exactly what it waits for, on this thread, listed order kept.
  std::vector<int> waited;
  loader.wait({7, 3}, [&](LoadResult&& r) {
    EXPECT_TRUE(r.ok());
    EXPECT_TRUE(r.slice.data == expectedSlice(photos[std::size_t(r.photo)], slice).data);
    waited.push_back(r.photo);
  });
  EXPECT_EQ(waited, (std::vector<int>{3, 7}));  // among waited photos: priority order
  EXPECT_EQ(loader.pending(), 7u);
  // A time budget decodes more than one per poll.
  std::set<int> rest;
  for (const auto& r : loader.poll(10s)) rest.insert(r.photo);
  EXPECT_EQ(rest, (std::set<int>{1, 2, 4, 5, 6, 8, 9}));
  loader.wait({1, 2, 100}, [](LoadResult&&) { ADD_FAILURE() << "nothing left"; });  // returns at once
}

TEST_F(ImageLoaderTest, WaitWithWorkersDeliversEverythingWaitedFor) {
  const Photo p = photo("cam", 12, 8, writeImage("a.png", 12, 8, 3, 1));
  ImageLoader loader({12, 8}, 3, 1 << 20);
  for (int i = 0; i < 200; ++i) loader.request(i, p, double(200 - i));
  std::vector<int> listed = {0, 50, 199, 7};
  std::set<int> delivered;
  loader.wait(listed, [&](LoadResult&& r) {
    EXPECT_TRUE(r.ok()) << r.error;
    EXPECT_TRUE(delivered.insert(r.photo).second);
  });
  for (int i : listed) EXPECT_TRUE(delivered.count(i)) << i;
  for (int i : listed) EXPECT_FALSE(loader.isPending(i));
  for (auto& r : pollAll(loader, 200 - delivered.size())) EXPECT_TRUE(delivered.insert(r.photo).second);
  EXPECT_EQ(delivered.size(), 200u);
}

// 4096 requests of tiny images with a cap that holds only a few: the cap holds, all are delivered.
TEST_F(ImageLoaderTest, MemoryCapHoldsUnderBurstOf4096) {
  const SliceSize slice{8, 8};
  constexpr int kFiles = 16, kPhotos = 4096;
  std::vector<Photo> files;
  std::vector<Image8> expected;
  for (int f = 0; f < kFiles; ++f) {
    files.push_back(photo("f", 8, 8, writeImage("t" + std::to_string(f) + ".png", 8, 8, f % 2 ? 4 : 3, f)));
    expected.push_back(expectedSlice(files.back(), slice));
  }
  std::vector<Photo> photos;
  for (int i = 0; i < kPhotos; ++i) {
    photos.push_back(files[std::size_t(i % kFiles)]);
    photos.back().camera.id = "cam" + std::to_string(i);
  }
  for (int threads : {0, 4}) {
    ImageLoader probe(slice, 0, 1 << 30);
    std::size_t job = 0;
    for (const Photo& f : files) job = std::max(job, probe.jobBytes(f));
    const std::size_t sliceBytes = 8 * 8 * 4;
    ASSERT_GT(job, sliceBytes);
    const std::size_t cap = 3 * job;  // three decodes, or a few more finished slices
    ImageLoader loader(slice, threads, cap);
    std::vector<LoadRequest> batch;
    for (int i = 0; i < kPhotos; ++i) batch.push_back({i, &photos[std::size_t(i)], double(i % 97)});
    loader.request(batch);
    std::this_thread::sleep_for(20ms);  // the workers fill the cap while nobody collects
    EXPECT_LE(loader.bytesInUse(), cap);
    EXPECT_EQ(loader.pending(), std::size_t(kPhotos));

    std::vector<int> count(kPhotos, 0);
    std::size_t delivered = 0, largestPoll = 0;
    const auto deadline = std::chrono::steady_clock::now() + 120s;
    while (delivered < std::size_t(kPhotos) && std::chrono::steady_clock::now() < deadline) {
      EXPECT_LE(loader.bytesInUse(), cap);
      const auto got = loader.poll(2ms);
      largestPoll = std::max(largestPoll, got.size());
      for (const auto& r : got) {
        ASSERT_TRUE(r.ok()) << r.error;
        ++count[std::size_t(r.photo)];
        ++delivered;
        EXPECT_TRUE(r.slice.data == expected[std::size_t(r.photo % kFiles)].data) << r.photo;
      }
    }
    EXPECT_EQ(delivered, std::size_t(kPhotos)) << threads << " threads";
    EXPECT_TRUE(std::all_of(count.begin(), count.end(), [](int c) { return c == 1; }));
    EXPECT_LE(loader.peakBytes(), cap) << threads << " threads";
    EXPECT_GE(loader.peakBytes(), job);
    EXPECT_LE(largestPoll, cap / sliceBytes);  // results held never exceed what the cap allows
    EXPECT_EQ(loader.bytesInUse(), 0u);
  }
}

TEST_F(ImageLoaderTest, BrokenImagesYieldErrorsNamingCameraAndField) {
  const std::string good = writeImage("good.png", 16, 12, 3, 1);
  const std::string garbage = (dir_ / "garbage.png").string();
  std::ofstream(garbage) << "this is not a PNG";
  const std::string truncated = (dir_ / "truncated.png").string();
  {
    std::ifstream in(good, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(truncated, std::ios::binary) << bytes.substr(0, 40);  // header intact, data cut
  }
  struct Case {
    Photo photo;
    std::string field;
  };
  const std::vector<Case> cases = {
      {photo("missing-image", 16, 12, (dir_ / "nope.png").string()), "image"},
      {photo("garbage-image", 16, 12, garbage), "image"},
      {photo("truncated-image", 16, 12, truncated), "image"},
      {photo("wrong-aspect", 16, 16, good), "image"},
      {photo("missing-mask", 16, 12, good, (dir_ / "nope_mask.png").string()), "mask"},
      {photo("garbage-mask", 16, 12, good, garbage), "mask"},
      {photo("wrong-aspect-mask", 16, 12, good, writeMask("square_mask.png", 8, 8)), "mask"},
  };
  for (int threads : {0, 2}) {
    ImageLoader loader({8, 8}, threads, 1 << 20);
    for (std::size_t i = 0; i < cases.size(); ++i) loader.request(int(i), cases[i].photo, 0.0);
    const Photo fine = photo("fine", 16, 12, good);
    loader.request(100, fine, 1.0);  // broken neighbours do not stop the rest
    const auto results = pollAll(loader, cases.size() + 1);
    ASSERT_EQ(results.size(), cases.size() + 1);
    for (const auto& r : results) {
      if (r.photo == 100) {
        EXPECT_TRUE(r.ok()) << r.error;
        continue;
      }
      const Case& c = cases[std::size_t(r.photo)];
      EXPECT_FALSE(r.ok()) << c.photo.camera.id;
      EXPECT_TRUE(r.slice.empty());
      EXPECT_NE(r.error.find("camera '" + c.photo.camera.id + "'"), std::string::npos) << r.error;
      EXPECT_NE(r.error.find("camera '" + c.photo.camera.id + "': " + c.field), std::string::npos) << r.error;
    }
    EXPECT_EQ(loader.bytesInUse(), 0u);
  }
  ImageLoader loader({8, 8}, 0, 1 << 20);
  EXPECT_THROW(loader.jobBytes(cases[0].photo), InputError);
  // A mask of another aspect ratio is refused from its header, before anything is decoded.
  try {
    loader.jobBytes(cases[6].photo);
    ADD_FAILURE() << "the 8x8 mask of a 16x12 camera was accepted by the probe";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("8x8 pixels, expected the camera's 16x12"), std::string::npos) << e.what();
  }
  // A FIFO as a photograph is refused without opening it (an open would wait for a writer).
  const std::string fifo = (dir_ / "pipe.png").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  try {
    loader.jobBytes(photo("fifo", 16, 12, fifo));
    ADD_FAILURE() << "a FIFO was probed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("FIFO"), std::string::npos) << e.what();
  }
}

TEST_F(ImageLoaderTest, ImageLargerThanTheCapIsAnErrorNotAHang) {
  const Photo big = photo("big", 64, 48, writeImage("big.png", 64, 48, 3, 1));
  const Photo small = photo("small", 8, 6, writeImage("small.png", 8, 6, 3, 2));
  ImageLoader probe({16, 12}, 0, 1 << 30);
  const std::size_t cap = probe.jobBytes(small) + 64;
  ASSERT_LT(cap, probe.jobBytes(big));
  for (int threads : {0, 2}) {
    ImageLoader loader({16, 12}, threads, cap);
    loader.request(0, big, 0.0);
    loader.request(1, small, 1.0);
    std::map<int, LoadResult> got;
    loader.wait({0, 1}, [&](LoadResult&& r) { got[r.photo] = std::move(r); });
    ASSERT_EQ(got.size(), 2u);
    EXPECT_FALSE(got[0].ok());
    EXPECT_NE(got[0].error.find("camera 'big': image"), std::string::npos) << got[0].error;
    EXPECT_NE(got[0].error.find("memory cap"), std::string::npos) << got[0].error;
    EXPECT_TRUE(got[1].ok()) << got[1].error;
    EXPECT_LE(loader.peakBytes(), cap);
  }
}

TEST_F(ImageLoaderTest, DestructorWithPendingWorkReturns) {
  const Photo p = photo("cam", 32, 32, writeImage("a.png", 32, 32, 3, 1));
  // Run in a thread so a hang fails this test instead of blocking the suite.
  auto done = std::async(std::launch::async, [&] {
    for (int round = 0; round < 20; ++round) {
      // Small cap: some workers block on memory, some decode, results wait uncollected.
      ImageLoader loader({16, 16}, 4, ImageLoader({16, 16}, 0, 1 << 30).jobBytes(p) * 2);
      for (int i = 0; i < 500; ++i) loader.request(i, p, double(i));
      if (round % 2) std::this_thread::sleep_for(1ms);
      if (round % 4 == 1) loader.poll();
    }
  });
  if (done.wait_for(60s) != std::future_status::ready) {
    std::fprintf(stderr, "ImageLoader destructor hung\n");
    std::_Exit(1);  // the hung thread cannot be joined
  }
  done.get();
}

// The renderer's streaming loop in miniature: 4096 photos, 64 slots; each frame needs <= 64 of
// them, renders what is resident, requests the rest nearest first and uploads what arrives; a
// batch frame waits. Evicted photos come back when a later view needs them again.
TEST_F(ImageLoaderTest, StreamsThroughSlotCache) {
  const SliceSize slice{8, 8};
  constexpr int kPhotos = 4096, kSlots = 64, kFiles = 8;
  std::vector<Photo> files;
  std::vector<Image8> expected;
  for (int f = 0; f < kFiles; ++f) {
    files.push_back(photo("f", 8, 8, writeImage("s" + std::to_string(f) + ".png", 8, 8, 3, f)));
    expected.push_back(expectedSlice(files.back(), slice));
  }
  std::vector<Photo> photos;
  for (int i = 0; i < kPhotos; ++i) {
    photos.push_back(files[std::size_t(i % kFiles)]);
    photos.back().camera.id = "cam" + std::to_string(i);
  }
  for (int threads : {0, 2}) {
    SlotCache cache(kSlots);
    std::vector<Image8> gpu(kSlots);  // stands for the texture array
    const std::size_t cap = 6 * ImageLoader(slice, 0, 1 << 30).jobBytes(files[0]);
    ImageLoader loader(slice, threads, cap);
    int reloads = 0;
    std::set<int> evicted, wantedNow;
    const auto upload = [&](LoadResult&& r) {
      ASSERT_TRUE(r.ok()) << r.error;
      // Pinned only when this frame needs it: a late arrival for an earlier view may be evicted.
      const auto g = cache.acquire(r.photo, wantedNow.count(r.photo) > 0);
      ASSERT_TRUE(g);  // at most 60 pinned of 64 slots
      if (g.evicted >= 0) evicted.insert(g.evicted);
      if (evicted.count(r.photo)) ++reloads;
      gpu[std::size_t(g.slot)] = std::move(r.slice);
    };
    // Views along a street and back again: photos near position v; every other view is a batch
    // frame (render, eval), which waits for full residency.
    std::vector<int> views;
    for (int v = 0; v < kPhotos; v += 512) views.push_back(v);
    for (int v = kPhotos - 512; v >= 0; v -= 1024) views.push_back(v);
    for (std::size_t vi = 0; vi < views.size(); ++vi) {
      std::vector<int> wanted;
      for (int k = 0; k < 60; ++k) wanted.push_back((views[vi] + k * 3) % kPhotos);
      wantedNow = std::set<int>(wanted.begin(), wanted.end());
      const auto missingNow = [&] {
        cache.unpinAll();
        std::vector<LoadRequest> missing;
        for (std::size_t k = 0; k < wanted.size(); ++k)
          if (!cache.pin(wanted[k])) missing.push_back({wanted[k], &photos[std::size_t(wanted[k])], double(k)});
        return missing;
      };
      if (vi % 2 == 0) {
        // Interactive frames: render with what is resident, stream the rest in.
        int frames = 0;
        for (; frames < 10000; ++frames) {
          const auto missing = missingNow();
          if (missing.empty()) break;
          loader.request(missing);
          for (auto& r : loader.poll(1ms)) upload(std::move(r));
          if (threads > 0) std::this_thread::sleep_for(50us);
        }
        EXPECT_LT(frames, 10000);
      } else {
        const auto missing = missingNow();
        loader.request(missing);
        std::vector<int> ids;
        for (const auto& m : missing) ids.push_back(m.photo);
        loader.wait(ids, upload);
      }
      for (int p : wanted) {
        const int s = cache.slotOf(p);
        ASSERT_GE(s, 0) << "photo " << p << " not resident";
        EXPECT_TRUE(gpu[std::size_t(s)].data == expected[std::size_t(p % kFiles)].data);
      }
      EXPECT_LE(loader.peakBytes(), cap);
    }
    EXPECT_GE(int(evicted.size()), 400);
    EXPECT_GE(reloads, 60);  // the way back needs photos evicted on the way out
  }
}

// A server of the test's folder for the remote reader: "http://h/NAME" is the file NAME, else an
// HTTP 404 as GDAL's client words it.
std::string gServed;
std::string serveFolder(const std::string& url, std::uint64_t, const std::string&, RemoteCache) {
  std::ifstream f(gServed + "/" + url.substr(url.rfind('/') + 1), std::ios::binary);
  if (!f) throw InputError(url + ": HTTP error code : 404");
  return std::string(std::istreambuf_iterator<char>(f), {});
}

// Photographs a server offers at several sizes (hv/util/image_sizes.h, a IIIF service): a preview
// first, then the image at the slice's width; previews before second jobs; wait() skips previews;
// a failed preview falls back to the full image.
TEST_F(ImageLoaderTest, PreviewFirstThenTheSliceWidth) {
  gServed = dir_.string();
  setRemoteReader(&serveFolder);
  clearImageSizes();
  resetImageFetchCounts();
  // Cameras of 160 x 120 in slices of 80 x 60: the slice needs the image 80 pixels wide.
  const SliceSize slice{80, 60};
  writeImage("a-160.png", 160, 120, 3, 1);
  const std::string a40 = writeImage("a-40.png", 40, 30, 3, 1);
  const std::string a80 = writeImage("a-80.png", 80, 60, 3, 1);
  writeImage("b-160.png", 160, 120, 3, 2);
  writeImage("b-40.png", 40, 30, 3, 2);
  writeImage("b-80.png", 80, 60, 3, 2);
  std::vector<int> asked;
  std::mutex askedMutex;
  const auto sizesOf = [&](const std::string& name, const std::string& preview) {
    ImageSizes z;
    z.preview = {preview, 40, 30};
    z.atWidth = [&, name](int w) {
      std::lock_guard lock(askedMutex);
      asked.push_back(w);
      const int x = std::min(w, 160);
      return SizedImageUrl{"http://h/" + name + "-" + std::to_string(x) + ".png", x, x * 3 / 4};
    };
    return z;
  };
  const Photo a = photo("a", 160, 120, "http://h/a-160.png"), b = photo("b", 160, 120, "http://h/b-160.png");
  registerImageSizes(a.imagePath, sizesOf("a", "http://h/a-40.png"));
  registerImageSizes(b.imagePath, sizesOf("b", "http://h/b-40.png"));
  {
    // One job per poll without threads: both previews (priority order), then both full images.
    ImageLoader loader(slice, 0, 64 << 20);
    loader.request(0, a, 1.0);
    loader.request(1, b, 2.0);
    std::vector<std::pair<int, bool>> order;
    std::vector<LoadResult> results;
    for (int i = 0; i < 4; ++i)
      for (auto& r : loader.poll()) {
        ASSERT_TRUE(r.ok()) << r.error;
        order.emplace_back(r.photo, r.preview);
        results.push_back(std::move(r));
      }
    EXPECT_EQ(order, (std::vector<std::pair<int, bool>>{{0, true}, {1, true}, {0, false}, {1, false}}));
    ASSERT_EQ(results.size(), 4u);
    EXPECT_EQ(results[0].imageWidth, 40);
    EXPECT_EQ(results[2].imageWidth, 80);
    EXPECT_EQ(results[2].imageHeight, 60);
    EXPECT_TRUE(loader.isPending(0) == false && loader.pending() == 0u);
    // The preview is the same image scaled up into the same slice layout; the full one is as
    // makeSliceImage makes it from the 80-pixel image.
    Photo local = a;
    local.imagePath = a40;
    EXPECT_TRUE(results[0].slice.data == expectedSlice(local, slice).data);
    local.imagePath = a80;
    EXPECT_TRUE(results[2].slice.data == expectedSlice(local, slice).data);
    EXPECT_EQ(asked, (std::vector<int>{80, 80}));
    const ImageFetchCounts c = imageFetchCounts();
    EXPECT_EQ(c.previews, 2u);
    EXPECT_EQ(c.images, 2u);
    EXPECT_EQ(c.previewBytes, fs::file_size(a40) + fs::file_size(dir_ / "b-40.png"));
    EXPECT_EQ(c.imageBytes, fs::file_size(a80) + fs::file_size(dir_ / "b-80.png"));
  }
  {
    // A batch frame waits for the full image: no preview.
    resetImageFetchCounts();
    ImageLoader loader(slice, 0, 64 << 20);
    loader.request(0, a, 1.0);
    std::vector<LoadResult> results;
    loader.wait({0}, [&](LoadResult&& r) { results.push_back(std::move(r)); });
    ASSERT_EQ(results.size(), 1u);
    EXPECT_TRUE(results[0].ok()) << results[0].error;
    EXPECT_FALSE(results[0].preview);
    EXPECT_EQ(results[0].imageWidth, 80);
    EXPECT_EQ(imageFetchCounts().previews, 0u);
    // Asked without a preview (a batch frame's request), with workers: the full image only.
    ImageLoader workers(slice, 2, 64 << 20);
    workers.request(0, a, 1.0, false);
    const auto only = pollAll(workers, 1);
    ASSERT_EQ(only.size(), 1u);
    EXPECT_FALSE(only[0].preview);
    EXPECT_EQ(only[0].imageWidth, 80);
    EXPECT_FALSE(workers.isPending(0));
    EXPECT_EQ(imageFetchCounts().previews, 0u);
  }
  {
    // With workers: the preview, then the full image.
    ImageLoader loader(slice, 2, 64 << 20);
    loader.request(0, a, 1.0);
    const auto both = pollAll(loader, 2);
    ASSERT_EQ(both.size(), 2u);
    EXPECT_TRUE(both[0].preview);
    EXPECT_FALSE(both[1].preview);
    EXPECT_EQ(both[1].imageWidth, 80);
  }
  {
    // wait() after the preview waits for the full image.
    ImageLoader loader(slice, 0, 64 << 20);
    loader.request(0, a, 1.0);
    const auto first = loader.poll();
    ASSERT_EQ(first.size(), 1u);
    EXPECT_TRUE(first[0].preview);
    EXPECT_TRUE(loader.isPending(0));
    std::vector<LoadResult> rest;
    loader.wait({0}, [&](LoadResult&& r) { rest.push_back(std::move(r)); });
    ASSERT_EQ(rest.size(), 1u);
    EXPECT_FALSE(rest[0].preview);
    EXPECT_EQ(rest[0].imageWidth, 80);
    EXPECT_FALSE(loader.isPending(0));
  }
  {
    // A preview that cannot be fetched is dropped: the full image comes, alone.
    const Photo c = photo("c", 160, 120, "http://h/b-160.png#c");
    registerImageSizes(c.imagePath, sizesOf("b", "http://h/missing.png"));
    ImageLoader loader(slice, 1, 64 << 20);
    loader.request(0, c, 1.0);
    std::vector<LoadResult> results;
    loader.wait({0}, [&](LoadResult&& r) { results.push_back(std::move(r)); });
    const auto late = loader.poll();
    ASSERT_EQ(results.size() + late.size(), 1u);
    const LoadResult& r = results.empty() ? late[0] : results[0];
    EXPECT_TRUE(r.ok()) << r.error;
    EXPECT_FALSE(r.preview);
  }
  clearImageSizes();
  setRemoteReader(nullptr);
}

}  // namespace
}  // namespace hv::ibr
