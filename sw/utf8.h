// Text that rtsim and rtref copy into a JSON output (the report keeps every
// flag, rtref's stats the scene's name) must be UTF-8: JSON cannot hold
// other bytes, and the library refuses them only as the output is written,
// after the run. A file's name on Linux may be any bytes, so it is checked
// before the run.
#pragma once
#include <string>

namespace rt {

// Empty if `text` is valid UTF-8; else the text as a JSON string with
// U+FFFD for each bad byte, to show in a message.
std::string notUtf8(const std::string& text);

}  // namespace rt
