// One deliberate bug per mode, for the sanitizer build to catch: the tests around it prove that
// build-asan/ is instrumented and that a report fails the process, so a sanitizer leg that checks
// nothing cannot pass unnoticed.
#include <climits>
#include <cstdio>
#include <cstring>

namespace {

// A use after free, which only ASan sees (UBSan's object-size check would catch an overflow
// first).
int UseAfterFree() {
  int* values = new int[4]();
  delete[] values;
  int* volatile dangling = values;
  return dangling[1];
}

int SignedOverflow() {
  volatile int large = INT_MAX;
  return large + 1;
}

int Leak() {
  int* volatile lost = new int[16]();
  lost = nullptr;
  return lost == nullptr ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s use-after-free|signed-overflow|leak\n", argv[0]);
    return 2;
  }
  if (std::strcmp(argv[1], "use-after-free") == 0) return UseAfterFree();
  if (std::strcmp(argv[1], "signed-overflow") == 0) return SignedOverflow();
  if (std::strcmp(argv[1], "leak") == 0) return Leak();
  std::fprintf(stderr, "%s: unknown mode %s\n", argv[0], argv[1]);
  return 2;
}
