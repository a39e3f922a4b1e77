#pragma once

#include <string>

namespace rfm::ros_glue {

// The one directory ~save_map and ~load_map may touch (parameter map_directory). A service's
// PATH is taken relative to it, or, when absolute, must lie under it; "..", and symbolic links
// that lead out of it, are refused, so a service call cannot write or read anywhere else.
class MapDirectory {
 public:
  // `directory` may start with "~/" (the user's home).
  explicit MapDirectory(const std::string& directory);

  const std::string& path() const { return directory_; }

  // Resolves a service's PATH prefix (the file names add .pgm, .yaml, .rfm) to a path inside the
  // directory. With `create`, the directory and missing directories under it are created.
  // False with `error` saying why, naming PATH and the directory.
  bool resolve(const std::string& requested, bool create, std::string& resolved,
               std::string* error) const;

  // Whether an existing file, symbolic links followed, still lies inside the directory.
  bool holds(const std::string& file, std::string* error) const;

 private:
  std::string directory_;
};

// "~/x" -> "$HOME/x"; other paths unchanged.
std::string expandHome(const std::string& path);

}  // namespace rfm::ros_glue
