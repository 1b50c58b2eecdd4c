// Config lookup for popcut: $POPCUT_CONFIG_DIR, then the installed share/popcut/configs, then the source tree.
#include "config_dir.h"

#include <cstdlib>
#include <system_error>

#include "popcut/error.h"

namespace popcut::cli {

namespace fs = std::filesystem;

std::vector<fs::path> config_dirs(const char* env_dir, const fs::path& exe) {
  if (env_dir && *env_dir) return {fs::path(env_dir)};
  std::vector<fs::path> dirs;
  if (!exe.empty()) dirs.push_back((exe.parent_path() / POPCUT_INSTALLED_CONFIG_REL).lexically_normal());
  dirs.emplace_back(POPCUT_SOURCE_CONFIG_DIR);
  return dirs;
}

namespace {

// The first `dirs[i] / relative` that is a directory (want_dir) or a regular file.
std::string find_in(const std::string& relative, const std::vector<fs::path>& dirs, bool want_dir) {
  std::string looked;
  for (const fs::path& d : dirs) {
    const fs::path f = d / relative;
    std::error_code ec;
    if (want_dir ? fs::is_directory(f, ec) : fs::is_regular_file(f, ec)) return f.string();
    looked += (looked.empty() ? "" : ", ") + f.string();
  }
  throw Error(ErrorCode::invalid_input, relative, "configs",
              "not found (looked at " + looked + "); set POPCUT_CONFIG_DIR to a configs/ directory or pass --profile");
}

std::vector<fs::path> own_config_dirs() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);  // Linux: popcut's own path
  return config_dirs(std::getenv("POPCUT_CONFIG_DIR"), ec ? fs::path() : exe);
}

}  // namespace

std::string find_config_file(const std::string& relative, const std::vector<fs::path>& dirs) {
  return find_in(relative, dirs, false);
}

std::string find_config_file(const std::string& relative) { return find_in(relative, own_config_dirs(), false); }

std::string find_config_dir(const std::string& relative) { return find_in(relative, own_config_dirs(), true); }

}  // namespace popcut::cli
