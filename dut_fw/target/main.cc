// The firmware's main loop: dut_fw's controller (dut_fw/dut_core_controller.h) behind the DUT side
// of the serial HIL link (dut_link/serial_session.h). USART1
// carries the link, and nothing but its frames; USART2 is the sensor nodes' UART bridge. The
// session waits for the runner's Hello, takes its DutConfig and then answers each SerialStep with
// a SerialCommand, the step's work measured with the board's SysTick cycle counter. The flash and
// RAM figures TargetInfo reports come from the image's own linker symbols.
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "dut_fw/dut_core_controller.h"
#include "dut_fw/serial_line_rates.h"
#include "dut_fw/target/board.h"
#include "dut_link/serial_session.h"

namespace target = hilrig::dut_fw::target;
namespace fw = hilrig::dut_fw;
namespace link = hilrig::dut_link;

// stm32f405.ld
extern "C" const std::uint8_t __flash_start[], __data_load[], __data_start[], __data_end[],
    __bss_end[], __stack_top[];

namespace {

class LinkUsart final : public link::LineSink {
 public:
  void Write(std::span<const std::uint8_t> bytes) override {
    target::Write(target::Port::kLink,
                  std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  }
};

class BridgeUsart final : public link::ByteSource {
 public:
  std::optional<std::uint8_t> ReadByte() override {
    return target::ReadByte(target::Port::kBridge);
  }
};

class SysTickClock final : public link::MonotonicClock {
 public:
  std::int64_t NowNs() override {
    return std::int64_t(target::MillisecondsSinceBoot()) * 1'000'000;
  }
};

class SysTickCycles final : public link::CycleCounter {
 public:
  std::uint32_t Cycles() override { return target::CycleCount(); }
};

std::uint32_t Span(const std::uint8_t* begin, const std::uint8_t* end) {
  return std::uint32_t(end - begin);
}

link::TargetDescription ThisTarget() {
  link::TargetDescription description;
  description.name = "dut_fw stm32f405";
  description.board = "stm32f405";
  description.core_clock_hz = target::kCoreClockHz;
  // The image in flash ends with the load copy of .data.
  description.flash_used_bytes = Span(__flash_start, __data_load) + Span(__data_start, __data_end);
  description.ram_used_bytes = Span(__data_start, __bss_end);
  description.stack_bytes = Span(__bss_end, __stack_top);
  return description;
}

std::uint64_t LostBytes(std::uint32_t (*count)(target::Port)) {
  return std::uint64_t(count(target::Port::kLink)) + count(target::Port::kBridge);
}

}  // namespace

int main() {
  target::InitBoard(fw::kLinkBaud, fw::kBridgeBaud);
  static LinkUsart link;
  static BridgeUsart bridge;
  static SysTickClock clock;
  static SysTickCycles cycles;
  static fw::DutCoreController<float> controller;
  static link::SerialDutSession session(controller, link, bridge, clock, cycles, ThisTarget());
  for (;;) {
    const std::optional<std::uint8_t> byte = target::ReadByte(target::Port::kLink);
    if (!byte) continue;
    session.SetReceiveLosses(LostBytes(target::Overruns), LostBytes(target::RingDrops));
    session.OnLinkByte(*byte);
  }
}
