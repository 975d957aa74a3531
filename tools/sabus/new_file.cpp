// New files under names a command makes (new_file.hpp).
#include "new_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace sabus::cli {
namespace {

namespace fs = std::filesystem;

// Names tried before giving up: a folder with a thousand findings of one seed
// and kind is not one to add to.
constexpr int kNamesTried = 1000;

bool write_all(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

}  // namespace

std::optional<fs::path> write_new_file(const fs::path& dir, const std::string& stem, const std::string& extension,
                                       const std::string& text, std::string& error) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    error = "cannot create the folder " + dir.string() + ": " + ec.message();
    return std::nullopt;
  }
  for (int n = 1; n <= kNamesTried; ++n) {
    std::string name = stem;
    if (n > 1) {  // (appended: "-" + std::to_string(n) draws GCC 12's false -Wrestrict)
      name += '-';
      name += std::to_string(n);
    }
    const fs::path file = dir / (name + extension);
    const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno == EEXIST) continue;
    if (fd < 0) {
      error = "cannot create " + file.string() + ": " + std::strerror(errno);
      return std::nullopt;
    }
    const bool written = write_all(fd, text);
    const int write_errno = errno;
    const bool closed = ::close(fd) == 0;
    if (written && closed) return file;
    error = file.string() + ": write failed: " + std::strerror(written ? errno : write_errno);
    fs::remove(file, ec);
    return std::nullopt;
  }
  error = "cannot create " + (dir / (stem + extension)).string() + ": it and " + std::to_string(kNamesTried - 1) +
          " numbered names beside it are taken";
  return std::nullopt;
}

}  // namespace sabus::cli
