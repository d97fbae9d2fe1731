// meshmark: text from a file or the user made safe to put in an error message.
#pragma once
#include <string>

namespace meshmark {

// `text` as valid UTF-8 for a message: well-formed UTF-8 sequences are kept, every other byte
// (invalid UTF-8, control characters) is written as \xNN; longer than `max_bytes` input bytes is
// cut and marked with "...". Python receives MeshError messages as str, so every message built
// from file content or a path goes through this.
std::string printable(const std::string& text, std::size_t max_bytes = 80);

}  // namespace meshmark
