// The board layer of the STM32F405 image, register-level (RM0090) with no vendor HAL: the core
// clock, a 1 kHz SysTick that also serves as the cycle counter for timing the control step (the
// DWT counter is not there under QEMU), and two USARTs whose receivers fill ring buffers from
// their interrupts. USART1 (PA9/PA10) carries the HIL link; USART2 (PA2/PA3) the sensor node's
// UART bridge. Transmission is polled: the main loop sends a reply and then waits for the next
// input anyway.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace hilrig::dut_fw::target {

inline constexpr std::uint32_t kCoreClockHz = 168'000'000;
inline constexpr std::uint32_t kSysTickHz = 1000;
inline constexpr std::uint32_t kCyclesPerTick = kCoreClockHz / kSysTickHz;
inline constexpr int kUsart1Irq = 37;  // RM0090 table 61
inline constexpr int kUsart2Irq = 38;

enum class Port : std::uint8_t { kLink, kBridge };  // USART1, USART2

enum class ClockSource : std::uint8_t {
  kPll168MHz,  // 8 MHz crystal through the PLL: the board's real speed
  // The RCC never reported the crystal or the PLL ready. Under QEMU the RCC is not modelled (the
  // core already runs at 168 MHz there); on a board it is a missing or dead crystal.
  kNoResponse,
};

// Clock tree, GPIO alternate functions, USART1 (the link) at `link_baud` and USART2 (the bridge)
// at `bridge_baud`, 8N1; SysTick; enables interrupts.
ClockSource InitBoard(std::uint32_t link_baud, std::uint32_t bridge_baud);

// Core cycles since InitBoard, from SysTick (under `-icount` QEMU: its virtual clock). Wraps after
// 2^32 cycles (25 s at 168 MHz), so only differences over shorter spans are meaningful.
std::uint32_t CycleCount();
std::uint32_t MillisecondsSinceBoot();

void Write(Port port, std::string_view text);
void WriteUnsigned(Port port, std::uint32_t value);
std::optional<std::uint8_t> ReadByte(Port port);
// Bytes lost because the ring buffer was full (the main loop fell behind).
std::uint32_t RingDrops(Port port);
// Bytes lost to a receiver overrun (the interrupt came too late for the data register).
std::uint32_t Overruns(Port port);

// Interrupt handlers, placed in the vector table by startup.cc.
extern "C" void OnSysTick();
extern "C" void OnUsart1();
extern "C" void OnUsart2();

}  // namespace hilrig::dut_fw::target
