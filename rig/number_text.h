// Numbers as text without a locale. In messages and reasons people read: six significant digits,
// the shortest form that shows them ("-1", "0.001", "1e-09", "5.56e+299"), where std::to_string
// writes a fixed six decimals ("0.000000" for 1e-9) and every digit of a huge number (300 of them
// for 1e300). In files read back: every digit the double needs, and no more.
#pragma once

#include <string>

namespace hilrig::rig {

std::string NumberText(double value);

// A duration in messages: NumberText and " s" ("0.2 s", "1e-05 s").
std::string SecondsText(double seconds);

// Numbers in files a program reads back (a sweep's runs.csv): "3.5", "0.20345678912345678", the
// shortest text that reads back as the same double.
std::string ExactNumber(double value);

// A speed against real time: whole numbers from 10 up ("2480x"), two significant digits below, so
// an emulated target's run reads "0.26x", not "0x" nor "0.262370x".
std::string FactorText(double factor);

}  // namespace hilrig::rig
