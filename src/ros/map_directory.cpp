#include "reflectance_field_map/ros/map_directory.h"

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace rfm::ros_glue {
namespace {

namespace fs = std::filesystem;

bool fail(std::string* error, const std::string& message) {
  if (error != nullptr) *error = message;
  return false;
}

// `path` (symbolic links of its existing part resolved) lies in or at `root` (canonical).
bool inside(const fs::path& root, const fs::path& path) {
  std::error_code ec;
  const fs::path resolved = fs::weakly_canonical(path, ec);
  if (ec) return false;
  const fs::path relative = resolved.lexically_relative(root);
  return !relative.empty() && *relative.begin() != "..";
}

}  // namespace

std::string expandHome(const std::string& path) {
  const char* home = std::getenv("HOME");
  if (home != nullptr && (path == "~" || path.rfind("~/", 0) == 0)) {
    return std::string(home) + path.substr(1);
  }
  return path;
}

MapDirectory::MapDirectory(const std::string& directory)
    : directory_(fs::path(expandHome(directory)).lexically_normal().string()) {}

bool MapDirectory::resolve(const std::string& requested, bool create, std::string& resolved,
                           std::string* error) const {
  const std::string where = " (map_directory " + directory_ + ")";
  if (requested.empty()) return fail(error, "empty path" + where);
  const fs::path asked(expandHome(requested));
  for (const fs::path& part : asked) {
    if (part == "..")
      return fail(error, "'" + requested + "' climbs out with '..': refused" + where);
  }
  if (asked.filename().empty() || asked.filename() == ".") {
    return fail(error, "'" + requested + "' names a directory, not a file prefix" + where);
  }
  std::error_code ec;
  if (create) fs::create_directories(directory_, ec);
  const fs::path root = fs::canonical(directory_, ec);
  if (ec || !fs::is_directory(root)) {
    return fail(error, "map_directory " + directory_ + " is not a directory" +
                           (ec ? ": " + ec.message() : std::string()));
  }
  const fs::path candidate =
      asked.is_absolute() ? asked.lexically_normal() : fs::path(directory_) / asked;
  if (!inside(root, candidate.parent_path())) {
    return fail(error, "'" + requested + "' lies outside map_directory " + directory_ +
                           ": save and load only there (a relative path is taken from it)");
  }
  if (create) {
    fs::create_directories(candidate.parent_path(), ec);
    if (ec) {
      return fail(error, "cannot create " + candidate.parent_path().string() + ": " + ec.message());
    }
  }
  resolved = candidate.string();
  return true;
}

bool MapDirectory::holds(const std::string& file, std::string* error) const {
  std::error_code ec;
  const fs::path root = fs::canonical(directory_, ec);
  if (ec) return fail(error, "map_directory " + directory_ + ": " + ec.message());
  if (!fs::exists(fs::symlink_status(file, ec))) return true;  // nothing there yet
  if (!inside(root, file)) {
    return fail(error,
                file + " is a symbolic link out of map_directory " + directory_ + ": refused");
  }
  return true;
}

}  // namespace rfm::ros_glue
