#pragma once

#include <stdexcept>
#include <string>

namespace rfm::tools {

// A file can't be read: what() names it and says why.
class ReadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The whole text of a file, gzip-compressed or not (zlib reads plain files as they are).
// Throws ReadError.
std::string readPossiblyCompressedText(const std::string& path);

}  // namespace rfm::tools
