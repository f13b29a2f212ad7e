#include "dut_fw/target/board.h"

#include <atomic>

#include "dut_fw/target/ring_buffer.h"

namespace hilrig::dut_fw::target {
namespace {

using Reg = volatile std::uint32_t;

Reg& At(std::uintptr_t address) { return *reinterpret_cast<Reg*>(address); }

// RM0090 section 7.3 (RCC) and 3.9 (flash interface).
constexpr std::uintptr_t kRcc = 0x40023800;
Reg& RccCr() { return At(kRcc + 0x00); }
Reg& RccPllCfgr() { return At(kRcc + 0x04); }
Reg& RccCfgr() { return At(kRcc + 0x08); }
Reg& RccAhb1Enr() { return At(kRcc + 0x30); }
Reg& RccApb1Enr() { return At(kRcc + 0x40); }
Reg& RccApb2Enr() { return At(kRcc + 0x44); }
Reg& FlashAcr() { return At(0x40023C00); }

constexpr std::uint32_t kCrHseOn = 1u << 16, kCrHseRdy = 1u << 17;
constexpr std::uint32_t kCrPllOn = 1u << 24, kCrPllRdy = 1u << 25;
// 8 MHz / M 8 * N 336 / P 2 = 168 MHz; / Q 7 = 48 MHz for USB. PLLP is encoded as P/2 - 1 = 0.
constexpr std::uint32_t kPllCfgr = 8u | (336u << 6) | (0u << 16) | (1u << 22) | (7u << 24);
// AHB / 1, APB1 / 4 (42 MHz, its maximum), APB2 / 2 (84 MHz, its maximum).
constexpr std::uint32_t kCfgrPrescalers = (0u << 4) | (5u << 10) | (4u << 13);
constexpr std::uint32_t kCfgrSwPll = 2u, kCfgrSwsMask = 3u << 2, kCfgrSwsPll = 2u << 2;
// Five wait states at 3.3 V and 168 MHz, with prefetch and both caches on.
constexpr std::uint32_t kFlashAcr = 5u | (1u << 8) | (1u << 9) | (1u << 10);
constexpr std::uint32_t kApb1HzAtPll = kCoreClockHz / 4;
constexpr std::uint32_t kApb2HzAtPll = kCoreClockHz / 2;
// Far longer than a crystal needs to start (~2 ms), short enough not to stall a boot on QEMU.
constexpr std::uint32_t kReadyPolls = 200'000;

bool WaitFor(Reg& reg, std::uint32_t mask, std::uint32_t value) {
  for (std::uint32_t poll = 0; poll < kReadyPolls; ++poll) {
    if ((reg & mask) == value) return true;
  }
  return false;
}

ClockSource StartPll() {
  RccCr() |= kCrHseOn;
  if (!WaitFor(RccCr(), kCrHseRdy, kCrHseRdy)) return ClockSource::kNoResponse;
  RccPllCfgr() = kPllCfgr;
  RccCr() |= kCrPllOn;
  if (!WaitFor(RccCr(), kCrPllRdy, kCrPllRdy)) return ClockSource::kNoResponse;
  FlashAcr() = kFlashAcr;
  RccCfgr() = kCfgrPrescalers | kCfgrSwPll;
  if (!WaitFor(RccCfgr(), kCfgrSwsMask, kCfgrSwsPll)) return ClockSource::kNoResponse;
  return ClockSource::kPll168MHz;
}

// RM0090 section 8.4 (GPIO): PA2/PA3 (USART2) and PA9/PA10 (USART1) to alternate function 7.
constexpr std::uintptr_t kGpioA = 0x40020000;
void RouteUsartPins() {
  RccAhb1Enr() |= 1u << 0;  // GPIOAEN
  Reg& moder = At(kGpioA + 0x00);
  Reg& afr_low = At(kGpioA + 0x20);
  Reg& afr_high = At(kGpioA + 0x24);
  for (std::uint32_t pin : {2u, 3u, 9u, 10u}) {
    moder = (moder & ~(3u << (2 * pin))) | (2u << (2 * pin));
    Reg& afr = pin < 8 ? afr_low : afr_high;
    const std::uint32_t shift = 4 * (pin % 8);
    afr = (afr & ~(0xFu << shift)) | (7u << shift);
  }
}

// RM0090 section 30.6 (USART).
constexpr std::uintptr_t kUsart1 = 0x40011000;
constexpr std::uintptr_t kUsart2 = 0x40004400;
constexpr std::uint32_t kSrOre = 1u << 3, kSrRxne = 1u << 5, kSrTxe = 1u << 7;
constexpr std::uint32_t kCr1Re = 1u << 2, kCr1Te = 1u << 3, kCr1RxneIe = 1u << 5, kCr1Ue = 1u << 13;

struct Usart {
  std::uintptr_t base;
  int irq;
  RingBuffer<1024> received;
  std::atomic<std::uint32_t> overruns{0};

  Reg& Sr() const { return At(base + 0x00); }
  Reg& Dr() const { return At(base + 0x04); }
  Reg& Brr() const { return At(base + 0x08); }
  Reg& Cr1() const { return At(base + 0x0C); }
};

Usart usart1{kUsart1, kUsart1Irq, {}};
Usart usart2{kUsart2, kUsart2Irq, {}};

Usart& UsartOf(Port port) { return port == Port::kLink ? usart1 : usart2; }

void StartUsart(Usart& usart, std::uint32_t bus_hz, std::uint32_t baud) {
  // Oversampling by 16: BRR holds bus_hz / baud with four fraction bits, rounded.
  usart.Brr() = (bus_hz + baud / 2) / baud;
  usart.Cr1() = kCr1Ue | kCr1Te | kCr1Re | kCr1RxneIe;
  At(0xE000E100 + 4 * std::uintptr_t(usart.irq / 32)) = 1u << (usart.irq % 32);  // NVIC_ISER
}

void OnUsart(Usart& usart) {
  // Reading SR then DR clears RXNE and an overrun alike.
  const std::uint32_t status = usart.Sr();
  if ((status & (kSrRxne | kSrOre)) == 0) return;
  const auto byte = std::uint8_t(usart.Dr());
  if ((status & kSrOre) != 0) {
    usart.overruns.store(usart.overruns.load(std::memory_order_relaxed) + 1,
                         std::memory_order_relaxed);
  }
  usart.received.Push(byte);
}

// ARMv7-M SysTick (B3.3), clocked by the core.
Reg& SysTickCtrl() { return At(0xE000E010); }
Reg& SysTickLoad() { return At(0xE000E014); }
Reg& SysTickVal() { return At(0xE000E018); }
constexpr std::uint32_t kSysTickEnableInterruptCoreClock = 0b111;

std::atomic<std::uint32_t> milliseconds{0};

}  // namespace

ClockSource InitBoard(std::uint32_t link_baud, std::uint32_t bridge_baud) {
  const ClockSource clock = StartPll();
  RccApb2Enr() |= 1u << 4;   // USART1EN
  RccApb1Enr() |= 1u << 17;  // USART2EN
  RouteUsartPins();
  StartUsart(usart1, kApb2HzAtPll, link_baud);
  StartUsart(usart2, kApb1HzAtPll, bridge_baud);
  SysTickLoad() = kCyclesPerTick - 1;
  SysTickVal() = 0;
  SysTickCtrl() = kSysTickEnableInterruptCoreClock;
  asm volatile("cpsie i" ::: "memory");
  return clock;
}

std::uint32_t MillisecondsSinceBoot() { return milliseconds.load(std::memory_order_relaxed); }

std::uint32_t CycleCount() {
  // SysTick counts down and the millisecond count moves in its interrupt; read until both belong
  // to the same tick.
  for (;;) {
    const std::uint32_t before = MillisecondsSinceBoot();
    const std::uint32_t down = SysTickVal();
    if (MillisecondsSinceBoot() == before)
      return before * kCyclesPerTick + (kCyclesPerTick - 1 - down);
  }
}

void Write(Port port, std::string_view text) {
  Usart& usart = UsartOf(port);
  for (const char c : text) {
    while ((usart.Sr() & kSrTxe) == 0) {
    }
    usart.Dr() = std::uint8_t(c);
  }
}

void WriteUnsigned(Port port, std::uint32_t value) {
  char digits[10];
  int count = 0;
  do {
    digits[count++] = char('0' + value % 10);
    value /= 10;
  } while (value != 0);
  char text[10];
  for (int i = 0; i < count; ++i) text[i] = digits[count - 1 - i];
  Write(port, std::string_view(text, std::size_t(count)));
}

std::optional<std::uint8_t> ReadByte(Port port) { return UsartOf(port).received.Pop(); }

std::uint32_t RingDrops(Port port) { return UsartOf(port).received.dropped(); }

std::uint32_t Overruns(Port port) { return UsartOf(port).overruns.load(std::memory_order_relaxed); }

extern "C" void OnSysTick() {
  milliseconds.store(milliseconds.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
}
extern "C" void OnUsart1() { OnUsart(usart1); }
extern "C" void OnUsart2() { OnUsart(usart2); }

}  // namespace hilrig::dut_fw::target
