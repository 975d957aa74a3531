// PtyLine: the server end of a pseudo-terminal, reached by clients through a
// symlink (`sabus sim --pty /tmp/rc3000`).
#include <fcntl.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>

#include "sabus/harness/line.hpp"

namespace sabus::harness {

namespace {

std::string read_link(const std::string& path) {
  char buf[PATH_MAX];
  const ssize_t n = ::readlink(path.c_str(), buf, sizeof buf - 1);
  if (n < 0) return {};
  return std::string(buf, static_cast<std::size_t>(n));
}

// Points link_path at target. Only a link to nothing (a stale one from a
// server that died: its pty is gone) is replaced, atomically by renaming a
// fresh link over it. A link to a pseudo-terminal that exists belongs to a
// server that is running (a pty's /dev/pts entry lives as long as its
// master is open): taking it over would cut that server's clients off and
// delete its link on exit. A link to anything else, and any other file,
// is left alone too. The check and the rename are two steps: a file created
// at link_path in between would be replaced, which is acceptable for a path
// the user named for this purpose.
void make_link(const std::string& link_path, const std::string& target, int unique) {
  struct stat st {};
  if (::lstat(link_path.c_str(), &st) == 0) {
    if (!S_ISLNK(st.st_mode))
      throw LineError("pty link " + link_path + " exists and is not a symbolic link; refusing to replace it");
    const std::string current = read_link(link_path);
    if (is_pseudo_terminal(link_path))
      throw LineError("pty link " + link_path + " points to " + current +
                      ", a pseudo-terminal in use (another sabus sim or proxy serves it); refusing to take it over. "
                      "Stop that server, or give another --link");
    if (::stat(link_path.c_str(), &st) == 0)
      throw LineError("pty link " + link_path + " points to " + current +
                      ", which is not a pseudo-terminal; refusing to replace it");
  }
  const std::string tmp = link_path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(unique);
  (void)::unlink(tmp.c_str());
  if (::symlink(target.c_str(), tmp.c_str()) != 0)
    throw LineError("cannot create the pty link " + link_path + ": " + posix::error_text(errno));
  if (::rename(tmp.c_str(), link_path.c_str()) != 0) {
    const int err = errno;
    (void)::unlink(tmp.c_str());
    throw LineError("cannot create the pty link " + link_path + ": " + posix::error_text(err));
  }
}

}  // namespace

std::unique_ptr<PtyLine> PtyLine::create(const std::string& link_path) {
  // posix_openpt rather than openpty(): it takes O_CLOEXEC, so the fds never
  // leak into a child another thread forks in between (and needs no -lutil).
  UniqueFd master(::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC));
  if (!master) throw LineError("cannot open a pseudo-terminal: " + posix::error_text(errno));
  if (::grantpt(master.get()) != 0 || ::unlockpt(master.get()) != 0)
    throw LineError("cannot unlock the pseudo-terminal: " + posix::error_text(errno));
  char name[PATH_MAX];
  if (::ptsname_r(master.get(), name, sizeof name) != 0)
    throw LineError("cannot name the pseudo-terminal: " + posix::error_text(errno));
  int fd;
  do fd = ::open(name, O_RDWR | O_NOCTTY | O_CLOEXEC);
  while (fd < 0 && errno == EINTR);
  UniqueFd slave(fd);
  if (!slave) throw LineError(std::string("cannot open ") + name + ": " + posix::error_text(errno));
  // The settings live in the slave's tty and stay while slave_ holds it open.
  // Clients usually set their own; these make a client that does not (cat,
  // a plain open()) see raw 8-bit bytes.
  posix::set_raw_8n1(slave.get(), 9600, std::string("pty ") + name);
  const int flags = ::fcntl(master.get(), F_GETFL);
  if (flags < 0 || ::fcntl(master.get(), F_SETFL, flags | O_NONBLOCK) != 0)
    throw LineError("cannot make the pty master non-blocking: " + posix::error_text(errno));

  std::unique_ptr<PtyLine> line(new PtyLine(std::move(master), std::move(slave), name));
  if (!link_path.empty()) {
    make_link(link_path, line->slave_name_, line->fd());
    line->link_path_ = link_path;
  }
  return line;
}

PtyLine::PtyLine(UniqueFd master, UniqueFd slave, std::string slave_name)
    : FdLine(std::move(master), Kind::pty_master), slave_(std::move(slave)), slave_name_(std::move(slave_name)) {}

PtyLine::~PtyLine() {
  // Only our own link: another server may have replaced it meanwhile.
  if (!link_path_.empty() && read_link(link_path_) == slave_name_) (void)::unlink(link_path_.c_str());
}

std::string PtyLine::describe() const {
  return "pty " + slave_name_ + (link_path_.empty() ? "" : " (link " + link_path_ + ")");
}

}  // namespace sabus::harness
