// meshmark: the one exception type of the library. Python sees it as meshmark.MeshError (a ValueError).
#pragma once
#include <stdexcept>
#include <string>

namespace meshmark {

// Raised for invalid input: the message says what is wrong and where (vertex, face, file line).
class MeshError : public std::runtime_error {
 public:
  explicit MeshError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace meshmark
