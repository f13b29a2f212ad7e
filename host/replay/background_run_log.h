// The run's log (run.mcap) written on a thread of its own. The run's loop only copies what it logs
// (each trace sample, and each input, CAN frame, step and command exchanged with the DUT) into a
// batch; full batches queue for the log's thread, which turns them into protobuf messages in the
// MCAP file (RunLogWriter and DutTrafficLog, unchanged) in the order they were logged. The loop
// waits only when the log's thread is a whole queue of batches behind.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "host/dut/dut_traffic.h"
#include "host/replay/dut_traffic_log.h"
#include "host/report/run_log.h"
#include "host/trace/trace_sample.h"
#include "rig/result.h"

namespace hilrig::host {

class BackgroundRunLog final : public DutTrafficSink {
 public:
  // Takes both logs over; `traffic` writes into `log`. Nothing else may use them from now on.
  BackgroundRunLog(std::unique_ptr<RunLogWriter> log, std::unique_ptr<DutTrafficLog> traffic);
  // Closes the log if Close was not called (its failure then goes unreported).
  ~BackgroundRunLog();
  BackgroundRunLog(const BackgroundRunLog&) = delete;
  BackgroundRunLog& operator=(const BackgroundRunLog&) = delete;

  // Each copies its argument into the current batch: no allocation once the batches have grown
  // to their size, and a wait only when a full batch finds the log's thread still busy.
  void Add(const TraceSample& sample);
  void Sent(const DutInput& input) override;
  void Received(const rig::TimedCanFrame& frame) override;
  void Asked(std::uint64_t tick, std::int64_t now_ns, std::optional<std::int64_t> wall_ns) override;
  void Answered(std::uint64_t tick, std::int64_t now_ns, const ActuatorMessage& command,
                std::optional<std::int64_t> wall_ns) override;

  // Writes what is left, stops the thread and closes the log: the log's first failure, if any.
  // A second call does nothing.
  rig::Result<void> Close();

 private:
  // What the loop logged since the last hand-over, each kind in its own vector (a trace sample is
  // far larger than an IMU sample) and `kinds` for their order.
  struct Batch {
    enum class Kind : std::uint8_t { kSample, kInput, kFrame, kAsked, kAnswered };
    struct Step {
      std::uint64_t tick = 0;
      std::int64_t now_ns = 0;
      std::optional<std::int64_t> wall_ns;
    };
    struct Answer {
      Step step;
      ActuatorMessage command;
    };
    std::vector<Kind> kinds;
    std::vector<TraceSample> samples;
    std::vector<DutInput> inputs;
    std::vector<rig::TimedCanFrame> frames;
    std::vector<Step> asks;
    std::vector<Answer> answers;
    void Clear();
  };

  void Logged(Batch::Kind kind);  // hands the batch over when it is full
  void HandOver();
  void Drain(const Batch& batch);
  void Loop();

  std::unique_ptr<RunLogWriter> log_;
  std::unique_ptr<DutTrafficLog> traffic_;
  // A ring of batches: the loop fills batches_[filling_], the log's thread drains the `queued_`
  // before it, oldest first.
  std::vector<Batch> batches_;
  std::size_t filling_ = 0;
  std::size_t queued_ = 0;
  std::mutex mutex_;
  std::condition_variable changed_;
  bool stopping_ = false;
  bool closed_ = false;
  std::thread thread_;
};

}  // namespace hilrig::host
