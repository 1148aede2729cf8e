#include "base/file_io.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

#include "base/error.h"

namespace fly {

namespace fs = std::filesystem;

void checkInputFile(const fs::path& path, std::string_view what, bool allowEmpty) {
  const SourceLocation loc{path.string()};
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) {
    throw InputError(loc, std::string(what) + " does not exist",
                     "check the path; relative paths are taken from the current directory or, inside a scene "
                     "file, from the scene file's directory");
  }
  if (fs::is_directory(st)) {
    throw InputError(loc, std::string(what) + " is a directory, not a file", "give the path of a file inside it");
  }
  if (!fs::is_regular_file(st)) {
    throw InputError(loc, std::string(what) + " is not a regular file", "give the path of a regular file");
  }
  if (!allowEmpty && fs::file_size(path, ec) == 0 && !ec) {
    throw InputError(loc, std::string(what) + " is empty (0 bytes)",
                     "the file was probably truncated while copying or saving; export it again");
  }
}

std::string readInputFile(const fs::path& path, std::string_view what, bool allowEmpty) {
  checkInputFile(path, what, allowEmpty);
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError({path.string()}, "cannot open " + std::string(what) + ": " + std::strerror(errno),
                     "check the file's permissions");
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError({path.string()}, "error while reading " + std::string(what));
  return std::move(ss).str();
}

void writeFileAtomic(const fs::path& path, std::string_view bytes) {
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::random_device rd;
  const fs::path tmp = dir / ("." + path.filename().string() + ".tmp" + std::to_string(rd()));
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) {
    throw std::runtime_error("cannot create " + tmp.string() + ": " + std::strerror(errno));
  }
  const char* p = bytes.data();
  size_t left = bytes.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int err = errno;
      ::close(fd);
      ::unlink(tmp.c_str());
      throw std::runtime_error("cannot write " + tmp.string() + ": " + std::strerror(err));
    }
    p += n;
    left -= static_cast<size_t>(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    throw std::runtime_error("cannot flush " + tmp.string() + ": " + std::strerror(err));
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    throw std::runtime_error("cannot rename " + tmp.string() + " to " + path.string() + ": " + std::strerror(err));
  }
}

}  // namespace fly
