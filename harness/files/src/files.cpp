// Files written whole or not at all (files.hpp).
#include "sabus/harness/files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <ostream>
#include <streambuf>
#include <vector>

namespace sabus::harness {
namespace {

std::string errno_text() { return std::strerror(errno); }

// Writes all of `text` to `fd`.
bool write_text(int fd, std::string_view text) {
  while (!text.empty()) {
    const ssize_t n = ::write(fd, text.data(), text.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    text.remove_prefix(static_cast<std::size_t>(n));
  }
  return true;
}

// Writes all of `text` to `fd`, flushed to the disk: a power cut after the
// rename or link leaves the whole text under the name, never an empty file.
bool write_all(int fd, std::string_view text) { return write_text(fd, text) && ::fsync(fd) == 0; }

// An output stream's buffer on a descriptor, in pieces of 64 KiB.
class FdBuf : public std::streambuf {
 public:
  explicit FdBuf(int fd) : fd_(fd), buf_(1 << 16) { setp(buf_.data(), buf_.data() + buf_.size()); }
  bool failed() const { return failed_; }

 protected:
  int sync() override {
    const bool ok = write_text(fd_, std::string_view(pbase(), static_cast<std::size_t>(pptr() - pbase())));
    failed_ |= !ok;
    setp(buf_.data(), buf_.data() + buf_.size());
    return ok ? 0 : -1;
  }
  int_type overflow(int_type c) override {
    if (sync() != 0) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) sputc(traits_type::to_char_type(c));
    return traits_type::not_eof(c);
  }

 private:
  int fd_;
  std::vector<char> buf_;
  bool failed_ = false;
};

// A new file beside `target` (created exclusively: nothing planted at a
// guessed name is written through) holding what `fill` writes; its name, or
// nullopt.
std::optional<std::string> write_temporary(const std::string& target, const Fill& fill, std::string& error) {
  std::string tmp = target + ".tmp.XXXXXX";
  const int fd = ::mkstemp(tmp.data());
  if (fd < 0) {
    error = target + ": cannot write a temporary file beside it: " + errno_text();
    return std::nullopt;
  }
  // mkstemp makes the file 0600; the file gets the mode any new file would.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  (void)::fchmod(fd, 0666 & ~mask);
  std::string filled;
  bool ok;
  {
    FdBuf buf(fd);
    std::ostream out(&buf);
    ok = fill(out, filled);
    out.flush();
    ok = ok && !buf.failed() && out.good();
  }
  const std::string why = errno_text();
  const bool synced = ok && ::fsync(fd) == 0;
  if (::close(fd) != 0 || !synced) {
    error = !filled.empty() ? filled : tmp + ": write failed: " + (synced ? errno_text() : why);
    ::unlink(tmp.c_str());
    return std::nullopt;
  }
  return tmp;
}

std::optional<std::string> write_temporary(const std::string& target, std::string_view text, std::string& error) {
  return write_temporary(target, Fill([&](std::ostream& out, std::string&) {
                           out.write(text.data(), static_cast<std::streamsize>(text.size()));
                           return true;
                         }),
                         error);
}

// Where `path` is written: itself, or for a symbolic link the file it names.
// "" with `error` set when that is not a regular file (or a link to none),
// saying what it is ("... is a directory, not a regular file; not replaced").
std::string replace_target(const std::string& path, std::string& error) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) return path;
    error = path + ": " + errno_text();
    return "";
  }
  std::string target = path;
  if (S_ISLNK(st.st_mode)) {
    std::error_code ec;
    const auto resolved = std::filesystem::canonical(path, ec);
    if (ec || ::stat(resolved.c_str(), &st) != 0) {
      error = path + " is a symbolic link to a file that does not exist; not written through it";
      return "";
    }
    target = resolved.string();
  }
  if (!S_ISREG(st.st_mode)) {
    const std::string kind = kind_of_file(st.st_mode);
    error = path + " is " + kind + (kind == "not a regular file" ? "" : ", not a regular file") + "; not replaced";
    return "";
  }
  return target;
}

// "STEM-N.EXT" beside `path`: "backup.json" -> "backup-2.json".
std::string numbered(const std::string& path, int n) {
  const std::filesystem::path p(path);
  return (p.parent_path() / (p.stem().string() + "-" + std::to_string(n) + p.extension().string())).string();
}

// A folder whose file system has no hard links (FAT, some network shares):
// the name is created exclusively and written in place, removed on failure.
bool write_exclusively(const std::string& name, std::string_view text, std::string& error) {
  const int fd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) {
    error = name + ": " + errno_text();
    return false;
  }
  const bool written = write_all(fd, text);
  if (::close(fd) != 0 || !written) {
    error = name + ": write failed: " + errno_text();
    ::unlink(name.c_str());
    return false;
  }
  return true;
}

}  // namespace

std::string kind_of_file(unsigned mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

bool replace_file(const std::string& path, std::string_view text, std::string& error) {
  return replace_file(path, Fill([&](std::ostream& out, std::string&) {
                        out.write(text.data(), static_cast<std::streamsize>(text.size()));
                        return true;
                      }),
                      error);
}

bool replace_file(const std::string& path, const Fill& fill, std::string& error) {
  const std::string target = replace_target(path, error);
  if (target.empty()) return false;
  const auto tmp = write_temporary(target, fill, error);
  if (!tmp) return false;
  // Checked again just before the rename: something may have been put there
  // while the text was written.
  std::string why;
  if (replace_target(path, why) != target) {
    error = (why.empty() ? path + " changed while it was written; not replaced" : why) + " (what was written is lost)";
  } else if (::rename(tmp->c_str(), target.c_str()) != 0) {
    error = target + ": cannot replace: " + errno_text();
  } else {
    return true;
  }
  ::unlink(tmp->c_str());
  return false;
}

std::optional<std::string> write_new_file(const std::string& path, std::string_view text, std::string& error) {
  const auto tmp = write_temporary(path, text, error);
  if (!tmp) return std::nullopt;
  std::optional<std::string> written;
  for (int i = 1; i <= kNewFileTries && !written; ++i) {
    const std::string name = i == 1 ? path : numbered(path, i);
    if (::link(tmp->c_str(), name.c_str()) == 0) {
      written = name;
    } else if (errno == EPERM || errno == EOPNOTSUPP || errno == ENOSYS) {
      if (::access(name.c_str(), F_OK) == 0) continue;  // taken: the next name
      if (!write_exclusively(name, text, error)) break;
      written = name;
    } else if (errno != EEXIST) {
      error = name + ": " + errno_text();
      break;
    }
  }
  ::unlink(tmp->c_str());
  if (!written && error.empty())
    error = path + " and the " + std::to_string(kNewFileTries - 1) + " numbered names after it are taken; nothing replaced";
  return written;
}

}  // namespace sabus::harness
