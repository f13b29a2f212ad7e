// Text for XML documents the rig writes (junit.xml, SVG plots): the five special characters as
// entities, and control characters XML 1.0 cannot carry replaced by '?', so a spec's names or a
// DUT's message can never break the file.
#pragma once

#include <string>

namespace hilrig::host {

std::string EscapeXmlText(const std::string& text);

}  // namespace hilrig::host
