// Start-up of the STM32F405 image: the vector table the core reads at reset, and Reset_Handler,
// which enables the FPU before any float instruction can run, copies .data from flash, zeroes .bss,
// runs the static constructors and enters main. Symbols come from stm32f405.ld.
#include <cstdint>

#include "dut_fw/target/board.h"

extern "C" {
extern std::uint32_t __stack_top;
extern std::uint32_t __data_start, __data_end, __data_load;
extern std::uint32_t __bss_start, __bss_end;
extern void (*__init_array_start[])();
extern void (*__init_array_end[])();

int main();
[[noreturn]] void Reset_Handler();
[[noreturn]] void Default_Handler();
}

namespace {

constexpr std::uintptr_t kCpacr = 0xE000ED88;
constexpr std::uint32_t kCpacrCp10Cp11Full = 0xFu << 20;

// Kept out of line and free of float so that nothing before the FPU is on needs it.
[[gnu::noinline]] void EnableFpu() {
  *reinterpret_cast<volatile std::uint32_t*>(kCpacr) |= kCpacrCp10Cp11Full;
  asm volatile("dsb\n isb" ::: "memory");
}

void CopyData() {
  const std::uint32_t* from = &__data_load;
  for (std::uint32_t* to = &__data_start; to < &__data_end;) *to++ = *from++;
}

void ZeroBss() {
  for (std::uint32_t* word = &__bss_start; word < &__bss_end;) *word++ = 0;
}

void RunConstructors() {
  for (void (**ctor)() = __init_array_start; ctor < __init_array_end; ++ctor) (*ctor)();
}

using Handler = void (*)();

// Cortex-M4 system exceptions, then the STM32F405's 82 peripheral interrupts (RM0090 table 61).
constexpr int kPeripheralIrqs = 82;
constexpr int kVectorCount = 16 + kPeripheralIrqs;

// Word 0 is the initial stack pointer, an address only the linker knows, so the table is a struct
// laid out like the core expects rather than an array of handlers.
struct BootTable {
  std::uint32_t* initial_stack;
  Handler vectors[kVectorCount - 1];  // vector 1 (reset) onwards
};

constexpr BootTable MakeBootTable() {
  namespace board = hilrig::dut_fw::target;
  BootTable table{&__stack_top, {}};
  const auto set = [&table](int exception, Handler handler) {
    table.vectors[exception - 1] = handler;
  };
  for (int exception = 2; exception < kVectorCount; ++exception) set(exception, Default_Handler);
  set(1, Reset_Handler);
  for (int reserved : {7, 8, 9, 10, 13}) set(reserved, nullptr);
  set(15, board::OnSysTick);
  set(16 + board::kUsart1Irq, board::OnUsart1);
  set(16 + board::kUsart2Irq, board::OnUsart2);
  return table;
}

}  // namespace

[[gnu::section(".isr_vector"), gnu::used]] constinit const BootTable kBootTable = MakeBootTable();

extern "C" void Reset_Handler() {
  EnableFpu();
  CopyData();
  ZeroBss();
  RunConstructors();
  main();
  for (;;) asm volatile("wfi");
}

// Faults and unexpected interrupts stop here, where a debugger finds them.
extern "C" void Default_Handler() {
  for (;;) asm volatile("bkpt 0");
}
