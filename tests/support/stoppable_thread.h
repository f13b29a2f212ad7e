// A program's main loop run in a thread of a test (dut_emu's serial and MAVLink modes): the loop
// takes a stop flag, and the thread sets it and joins however the test ends, a failed ASSERT
// included, so no test leaves a loop running.
#pragma once

#include <atomic>
#include <functional>
#include <thread>

namespace hilrig::test_support {

class StoppableThread {
 public:
  // Runs `loop(&stop)` at once; its return value is the exit code Join gives.
  explicit StoppableThread(std::function<int(const std::atomic<bool>* stop)> loop)
      : thread_([this, loop = std::move(loop)] { exit_code_ = loop(&stop_); }) {}
  ~StoppableThread() {
    stop_ = true;
    Join();
  }
  StoppableThread(const StoppableThread&) = delete;
  StoppableThread& operator=(const StoppableThread&) = delete;

  // Waits for the loop to end by itself; its exit code.
  int Join() {
    if (thread_.joinable()) thread_.join();
    return exit_code_;
  }

 private:
  std::atomic<bool> stop_{false};
  int exit_code_ = -1;
  std::thread thread_;
};

}  // namespace hilrig::test_support
