#include "reflectance_field_map/tools/compressed_text.h"

#include <zlib.h>

#include <cerrno>
#include <cstring>
#include <memory>

namespace rfm::tools {

std::string readPossiblyCompressedText(const std::string& path) {
  const std::unique_ptr<gzFile_s, int (*)(gzFile)> file(gzopen(path.c_str(), "rb"), gzclose);
  if (!file) {
    throw ReadError("cannot read " + path + ": " +
                    (errno != 0 ? std::strerror(errno) : "cannot open it"));
  }
  std::string text;
  char buffer[1 << 16];
  while (true) {
    const int n = gzread(file.get(), buffer, sizeof(buffer));
    if (n < 0) {
      int code = 0;
      const char* message = gzerror(file.get(), &code);
      throw ReadError("cannot read " + path + ": " +
                      (code == Z_ERRNO ? std::strerror(errno) : message));
    }
    if (n == 0) break;
    text.append(buffer, static_cast<std::size_t>(n));
  }
  int code = Z_OK;
  const char* message = gzerror(file.get(), &code);
  if (code != Z_OK) throw ReadError("cannot read " + path + ": " + message);
  return text;
}

}  // namespace rfm::tools
