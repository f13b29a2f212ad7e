#include "host/fidelity/trace_capture.h"

namespace hilrig::host {

void CapturedTrace::Add(const TraceSample& sample) {
  time_s.push_back(sample.time_s);
  position_m.push_back(sample.position_m);
  grasp_force_n.push_back(sample.grasp_force_n);
  load_n.push_back(sample.load_n);
}

}  // namespace hilrig::host
