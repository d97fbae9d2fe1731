// meshmark: the lower-case extension of a path, without the dot ("" when there is none), shared by
// read_mesh (read_mesh.cpp) and write_mesh (mesh_io.cpp), which pick the format by it. Private to
// native/src.
#pragma once
#include <algorithm>
#include <cctype>
#include <string>

namespace meshmark::detail {

inline std::string file_extension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of("/\\");
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace meshmark::detail
