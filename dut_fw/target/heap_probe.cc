// An image that allocates, built only by tests/target/no_heap_link_test.sh to show that the
// firmware's link refuses the heap. It brings the _sbrk newlib's allocator needs, so without the
// guard it would link and run.
#include <cstddef>
#include <cstdlib>

extern "C" void* _sbrk(std::ptrdiff_t increment) {
  alignas(8) static char arena[1024];
  static std::size_t used = 0;
  char* const start = arena + used;
  used += std::size_t(increment);
  return start;
}

int main() {
  void* volatile block = std::malloc(16);
  return block != nullptr ? 0 : 1;
}
