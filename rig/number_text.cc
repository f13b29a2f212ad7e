#include "rig/number_text.h"

#include <sstream>

namespace hilrig::rig {

std::string NumberText(double value) {
  std::ostringstream text;
  text << value;  // the stream's default: %g with six significant digits
  return text.str();
}

}  // namespace hilrig::rig
