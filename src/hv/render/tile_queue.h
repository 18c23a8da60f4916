// The work queue shared by the streamed geometry tiles (render/terrain_stream.h,
// render/building_stream.h): requests ordered by priority (lower first) and deduplicated, read by
// worker threads or, with none (the browser build), on the caller's thread a bounded amount at a
// time, as ibr::ImageLoader does with photographs. GL-free.
//
// `Job` is what a request carries to the reader (the terrain: the resident ancestors' samples);
// `Result` is what the reader gives back. A tile is in at most one of: queued, being read, read
// and not taken yet. Member functions other than the reader are called from one thread (the
// render thread); the workers only touch the queue and the results under the lock.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <tuple>
#include <utility>
#include <vector>

namespace hv::render {

template <class Job, class Result>
class TileQueue {
 public:
  using Reader = std::function<Result(std::uint64_t id, const Job& job)>;

  // Throws std::invalid_argument for a negative thread count or no reader.
  TileQueue(int workerThreads, Reader reader) : reader_(std::move(reader)) {
    if (workerThreads < 0) throw std::invalid_argument("tile queue: negative worker thread count");
    if (!reader_) throw std::invalid_argument("tile queue: no reader");
    for (int i = 0; i < workerThreads; ++i) workers_.emplace_back([this] { workerLoop(); });
  }
  ~TileQueue() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
      queued_.clear();
      order_.clear();
    }
    workCv_.notify_all();
    for (std::thread& t : workers_) t.join();
  }
  TileQueue(const TileQueue&) = delete;
  TileQueue& operator=(const TileQueue&) = delete;

  // Whether `id` is queued, being read, or read and not taken yet.
  bool inFlight(std::uint64_t id) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return queued_.count(id) || running_.count(id) || readyIds_.count(id);
  }

  // Queues `id` at `priority` with `job`; a tile already queued only has its priority lowered (to
  // the smaller of the two), one being read or read is left alone.
  void request(std::uint64_t id, double priority, Job job) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (running_.count(id) || readyIds_.count(id)) return;
      if (const auto it = queued_.find(id); it != queued_.end()) {
        if (priority < it->second.priority) {
          order_.erase({it->second.priority, it->second.seq, id});
          it->second.priority = priority;
          order_.insert({priority, it->second.seq, id});
        }
        return;
      }
      Entry e{std::move(job), priority, nextSeq_++};
      order_.insert({priority, e.seq, id});
      queued_.emplace(id, std::move(e));
    }
    workCv_.notify_one();
  }

  // Never blocks on reads: the results finished so far. With no worker threads it first reads the
  // queue's head on this thread, then more while `inlineBudget` has not elapsed.
  std::deque<Result> take(std::chrono::microseconds inlineBudget) {
    std::deque<Result> done;
    std::unique_lock<std::mutex> lock(mutex_);
    if (workers_.empty()) {
      const auto start = std::chrono::steady_clock::now();
      while (runOne(lock) && std::chrono::steady_clock::now() - start < inlineBudget) {
      }
    }
    done.swap(ready_);
    readyIds_.clear();
    return done;
  }

  // Blocks until nothing is queued or being read, handing the results to `sink` as they arrive.
  void waitAll(const std::function<void(std::deque<Result>&)>& sink) {
    for (;;) {
      std::deque<Result> done;
      bool finished = false;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        if (workers_.empty())
          runOne(lock);
        else
          doneCv_.wait(lock, [&] { return !ready_.empty() || (order_.empty() && running_.empty()); });
        done.swap(ready_);
        readyIds_.clear();
        finished = order_.empty() && running_.empty();
      }
      sink(done);
      if (finished) return;
    }
  }

  std::size_t pending() const {  // queued, being read, or read and not taken
    const std::lock_guard<std::mutex> lock(mutex_);
    return queued_.size() + running_.size() + ready_.size();
  }
  int workerThreads() const { return int(workers_.size()); }

 private:
  struct Entry {
    Job job;
    double priority = 0.0;
    std::uint64_t seq = 0;
  };
  using Key = std::tuple<double, std::uint64_t, std::uint64_t>;  // priority, arrival, id

  // Takes the queue's head and reads it with the lock released. False when nothing is queued.
  bool runOne(std::unique_lock<std::mutex>& lock) {
    if (order_.empty()) return false;
    const std::uint64_t id = std::get<2>(*order_.begin());
    order_.erase(order_.begin());
    Job job = std::move(queued_.at(id).job);
    queued_.erase(id);
    running_.insert(id);
    lock.unlock();
    Result r = reader_(id, job);
    lock.lock();
    running_.erase(id);
    ready_.push_back(std::move(r));
    readyIds_.insert(id);
    doneCv_.notify_all();
    return true;
  }
  void workerLoop() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      workCv_.wait(lock, [&] { return stop_ || !order_.empty(); });
      if (stop_) return;
      runOne(lock);
    }
  }

  const Reader reader_;
  mutable std::mutex mutex_;
  std::condition_variable workCv_, doneCv_;
  bool stop_ = false;
  std::uint64_t nextSeq_ = 0;
  std::map<std::uint64_t, Entry> queued_;
  std::set<Key> order_;
  std::set<std::uint64_t> running_, readyIds_;
  std::deque<Result> ready_;
  std::vector<std::thread> workers_;
};

}  // namespace hv::render
