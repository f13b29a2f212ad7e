#include "host/replay/background_run_log.h"

#include <utility>

namespace hilrig::host {
namespace {

// Entries per hand-over: few enough that a batch stays in the cache, many enough that the lock is
// taken a few hundred times in a run of a hundred thousand messages.
constexpr std::size_t kBatchEntries = 1024;
// Batches in the ring: the log's thread shares a core with the MCAP writer's compression, and
// works in bursts; the loop runs on while it catches up. About 3 MB when full.
constexpr std::size_t kBatches = 16;

}  // namespace

void BackgroundRunLog::Batch::Clear() {
  kinds.clear();
  samples.clear();
  inputs.clear();
  frames.clear();
  asks.clear();
  answers.clear();
}

BackgroundRunLog::BackgroundRunLog(std::unique_ptr<RunLogWriter> log,
                                   std::unique_ptr<DutTrafficLog> traffic)
    : log_(std::move(log)), traffic_(std::move(traffic)), batches_(kBatches) {
  thread_ = std::thread([this] { Loop(); });
}

BackgroundRunLog::~BackgroundRunLog() { (void)Close(); }

void BackgroundRunLog::Add(const TraceSample& sample) {
  batches_[filling_].samples.push_back(sample);
  Logged(Batch::Kind::kSample);
}

void BackgroundRunLog::Sent(const DutInput& input) {
  batches_[filling_].inputs.push_back(input);
  Logged(Batch::Kind::kInput);
}

void BackgroundRunLog::Received(const rig::TimedCanFrame& frame) {
  batches_[filling_].frames.push_back(frame);
  Logged(Batch::Kind::kFrame);
}

void BackgroundRunLog::Asked(std::uint64_t tick, std::int64_t now_ns,
                             std::optional<std::int64_t> wall_ns) {
  batches_[filling_].asks.push_back({tick, now_ns, wall_ns});
  Logged(Batch::Kind::kAsked);
}

void BackgroundRunLog::Answered(std::uint64_t tick, std::int64_t now_ns,
                                const ActuatorMessage& command,
                                std::optional<std::int64_t> wall_ns) {
  batches_[filling_].answers.push_back({{tick, now_ns, wall_ns}, command});
  Logged(Batch::Kind::kAnswered);
}

void BackgroundRunLog::Logged(Batch::Kind kind) {
  Batch& batch = batches_[filling_];
  batch.kinds.push_back(kind);
  if (batch.kinds.size() >= kBatchEntries) HandOver();
}

// Queues the full batch and moves on to the next one of the ring, once the log's thread has
// drained it (it has kept its capacity: nothing is allocated).
void BackgroundRunLog::HandOver() {
  std::unique_lock lock(mutex_);
  ++queued_;
  filling_ = (filling_ + 1) % batches_.size();
  changed_.notify_all();
  // All queued, the next one to fill among them: wait for the log's thread to drain it.
  changed_.wait(lock, [this] { return queued_ < batches_.size(); });
}

void BackgroundRunLog::Drain(const Batch& batch) {
  std::size_t sample = 0, input = 0, frame = 0, ask = 0, answer = 0;
  for (const Batch::Kind kind : batch.kinds) {
    switch (kind) {
      case Batch::Kind::kSample:
        log_->Add(batch.samples[sample++]);
        break;
      case Batch::Kind::kInput:
        traffic_->Sent(batch.inputs[input++]);
        break;
      case Batch::Kind::kFrame:
        traffic_->Received(batch.frames[frame++]);
        break;
      case Batch::Kind::kAsked: {
        const Batch::Step& step = batch.asks[ask++];
        traffic_->Asked(step.tick, step.now_ns, step.wall_ns);
        break;
      }
      case Batch::Kind::kAnswered: {
        const Batch::Answer& done = batch.answers[answer++];
        traffic_->Answered(done.step.tick, done.step.now_ns, done.command, done.step.wall_ns);
        break;
      }
    }
  }
}

void BackgroundRunLog::Loop() {
  std::unique_lock lock(mutex_);
  while (true) {
    changed_.wait(lock, [this] { return queued_ > 0 || stopping_; });
    if (queued_ == 0) return;  // stopping, nothing queued
    // The queued batches are the `queued_` ones before filling_ in the ring.
    const std::size_t oldest = (filling_ + batches_.size() - queued_) % batches_.size();
    lock.unlock();
    Drain(batches_[oldest]);
    batches_[oldest].Clear();
    lock.lock();
    --queued_;
    changed_.notify_all();
  }
}

rig::Result<void> BackgroundRunLog::Close() {
  if (closed_) return {};
  closed_ = true;
  {
    std::lock_guard lock(mutex_);
    if (!batches_[filling_].kinds.empty()) {
      ++queued_;
      filling_ = (filling_ + 1) % batches_.size();
    }
    stopping_ = true;
  }
  changed_.notify_all();
  thread_.join();
  return log_->Close();
}

}  // namespace hilrig::host
