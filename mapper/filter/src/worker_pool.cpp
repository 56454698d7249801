#include "ogf/filter/worker_pool.hpp"

#include <exception>

namespace ogf::filter {

WorkerPool::WorkerPool(int threads) {
  const std::size_t extra = threads > 1 ? static_cast<std::size_t>(threads - 1) : 0;
  workers_.reserve(extra);
  for (std::size_t w = 1; w <= extra; ++w) {
    workers_.emplace_back([this, w] { work(w); });
  }
}

WorkerPool::~WorkerPool() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  for (std::thread& t : workers_) {
    t.join();
  }
}

void WorkerPool::run(const std::function<void(std::size_t)>& share) {
  if (workers_.empty()) {
    share(0);
    return;
  }
  {
    const std::lock_guard lock(mutex_);
    share_ = &share;
    running_ = workers_.size();
    ++generation_;
  }
  wake_.notify_all();
  // The workers hold `share` until they return: wait for them even when the calling thread's share throws.
  std::exception_ptr thrown;
  try {
    share(0);
  } catch (...) {
    thrown = std::current_exception();
  }
  std::unique_lock lock(mutex_);
  done_.wait(lock, [&] { return running_ == 0; });
  share_ = nullptr;
  if (thrown) {
    std::rethrow_exception(thrown);
  }
}

void WorkerPool::work(std::size_t w) {
  std::uint64_t seen = 0;
  for (;;) {
    const std::function<void(std::size_t)>* share = nullptr;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stopping_ || generation_ != seen; });
      if (stopping_) {
        return;
      }
      seen = generation_;
      share = share_;
    }
    (*share)(w);
    bool last = false;
    {
      const std::lock_guard lock(mutex_);
      last = --running_ == 0;
    }
    if (last) {
      done_.notify_one();
    }
  }
}

}  // namespace ogf::filter
