// The filter's threads, started once and kept: update() hands them a share of a stage's work several times
// a scan (the colours of the sweep, the early drop of clamped free measurements, the grouping), and a
// thread started for each would cost tens of microseconds every time. The calling thread takes share 0, so
// a pool of N threads starts N − 1.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace ogf::filter {

class WorkerPool {
 public:
  // `threads` ≥ 1, the calling thread among them.
  explicit WorkerPool(int threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  std::size_t threads() const { return workers_.size() + 1; }
  // Calls share(w) for every w in [0, threads()), w = 0 on the calling thread, and returns when all have
  // returned. A worker's share must not throw (that ends the process, as in any thread); an exception from
  // share 0 is thrown on once the workers are done. Not reentrant: one run at a time.
  void run(const std::function<void(std::size_t)>& share);

 private:
  void work(std::size_t w);

  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;
  const std::function<void(std::size_t)>* share_ = nullptr;
  std::uint64_t generation_ = 0;  // one more for each run
  std::size_t running_ = 0;       // workers still in the current run's share
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

// Splits [0, n) into `parts` consecutive ranges of nearly equal size: range p is [begin(p), begin(p + 1)).
struct EvenSplit {
  std::size_t n;
  std::size_t parts;
  std::size_t begin(std::size_t p) const { return n * p / parts; }
};

}  // namespace ogf::filter
