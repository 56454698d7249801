#include "ogf/transport/dispatch_thread.hpp"

#include <spdlog/spdlog.h>

namespace ogf::transport {

namespace {

// How often the thread looks at its stop flag while nothing arrives.
constexpr int kPollMs = 100;

}  // namespace

DispatchThread::DispatchThread(lcm::LCM& lcm) : lcm_(lcm), thread_([this] { run(); }) {}

DispatchThread::~DispatchThread() {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
}

void DispatchThread::run() {
  while (!stop_.load()) {
    if (lcm_.handleTimeout(kPollMs) < 0) {
      spdlog::error("LCM dispatch thread: the bus reported an error; nothing more is received on it");
      return;
    }
  }
}

}  // namespace ogf::transport
