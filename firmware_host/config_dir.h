// Where popcut finds its configs/ (device profiles): the environment, an installed tree, or the source tree.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace popcut::cli {

// The directories searched, in order: $POPCUT_CONFIG_DIR alone when it is set (an explicit choice
// is never second-guessed); otherwise <exe dir>/../share/popcut/configs (an installed popcut),
// then the source tree's configs/ (running from a build tree). `exe` is popcut's own path.
std::vector<std::filesystem::path> config_dirs(const char* env_dir, const std::filesystem::path& exe);

// `relative` (e.g. "devices/sim.toml") in the first directory holding it; throws
// Error(invalid_input) naming every place looked at when none does.
std::string find_config_file(const std::string& relative, const std::vector<std::filesystem::path>& dirs);

// The same for this process: its environment and /proc/self/exe.
std::string find_config_file(const std::string& relative);

// A directory (e.g. "devices") found the same way.
std::string find_config_dir(const std::string& relative);

}  // namespace popcut::cli
