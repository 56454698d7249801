// An LCM instance dispatched on a thread of its own. Each udpm instance has its own socket, receive thread
// and subscription queues, so what is subscribed on it never waits in another instance's queue: ogf-mapper
// receives its map services there, and no volume of queries holds up the scans and poses of its main
// instance (which LCM would otherwise dispatch one by one in arrival order).
#pragma once

#include <lcm/lcm-cpp.hpp>

#include <atomic>
#include <thread>

namespace ogf::transport {

class DispatchThread {
 public:
  // Starts dispatching `lcm`, which must be able to receive (receiveProblem) and outlive this.
  explicit DispatchThread(lcm::LCM& lcm);
  // Stops after the handler in hand; nothing is dispatched afterwards.
  ~DispatchThread();
  DispatchThread(const DispatchThread&) = delete;
  DispatchThread& operator=(const DispatchThread&) = delete;

 private:
  void run();

  lcm::LCM& lcm_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace ogf::transport
