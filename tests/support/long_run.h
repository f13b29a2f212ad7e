// How long the long-run tests (the integrators over a simulated hour) run. The normal build runs
// the whole hour at 1 kHz. The sanitizer build, where AddressSanitizer makes each of these steps 20
// to 70 times slower, runs a tenth of it: the same code paths under the same bounds (the drifts the
// bounds hold grow with the run, so a shorter one meets them with room to spare), in a tenth of
// the time; the hour itself stays in the normal leg.
#pragma once

namespace hilrig::test_support {

#ifdef HILRIG_SANITIZED_BUILD
inline constexpr int kLongRunSteps = 360'000;
#else
inline constexpr int kLongRunSteps = 3'600'000;
#endif

}  // namespace hilrig::test_support
