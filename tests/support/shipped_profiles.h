// The device profiles shipped in configs/devices/, for tests that must cover every one of them.
#pragma once

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace popcut::testing {

// Sorted paths of configs/devices/*.toml (POPCUT_SOURCE_DIR is defined for every test target).
inline std::vector<std::string> shipped_profiles() {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(std::string(POPCUT_SOURCE_DIR) + "/configs/devices")) {
    if (e.path().extension() == ".toml") files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace popcut::testing
