// Waiting on a file descriptor with a deadline, for the transports of the HIL link (the TCP link,
// the byte streams of a serial link): poll(2) with what is left of the deadline, EINTR retried. The
// deadlines are wall time by nature: they bound how long a peer may take.
#pragma once

#include <chrono>

namespace hilrig::host {

using Deadline = std::chrono::steady_clock::time_point;

Deadline DeadlineIn(int timeout_ms);
int MillisecondsLeft(Deadline deadline);
// poll(2) for `events` on fd; >0 ready, 0 timed out, <0 failed.
int WaitFor(int fd, short events, Deadline deadline);

}  // namespace hilrig::host
