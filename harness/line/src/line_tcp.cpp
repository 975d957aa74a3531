// TcpLine and TcpListener: raw bytes over TCP, as to and from a serial device
// server (no Telnet/RFC 2217 negotiation).
#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

#include "sabus/harness/line.hpp"

namespace sabus::harness {

namespace {

using Clock = std::chrono::steady_clock;

std::string endpoint(const std::string& host, std::uint16_t port) {
  // "[::1]:4001" for IPv6 literals, "127.0.0.1:4001" otherwise.
  return (host.find(':') != std::string::npos ? "[" + host + "]" : host) + ":" + std::to_string(port);
}

std::string address_text(const sockaddr_storage& sa) {
  char host[NI_MAXHOST], serv[NI_MAXSERV];
  if (::getnameinfo(reinterpret_cast<const sockaddr*>(&sa), sizeof sa, host, sizeof host, serv, sizeof serv,
                    NI_NUMERICHOST | NI_NUMERICSERV) != 0)
    return "?";
  return endpoint(host, static_cast<std::uint16_t>(std::stoi(serv)));
}

struct AddrInfo {
  addrinfo* list = nullptr;
  ~AddrInfo() {
    if (list != nullptr) ::freeaddrinfo(list);
  }
};

void resolve(const std::string& host, std::uint16_t port, bool passive, AddrInfo& out) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_NUMERICSERV | (passive ? AI_PASSIVE : 0);
  const std::string serv = std::to_string(port);
  int r = ::getaddrinfo(host.empty() ? nullptr : host.c_str(), serv.c_str(), &hints, &out.list);
  for (int retry = 0; r == EAI_AGAIN && retry < 2; ++retry)  // a temporary failure of the resolver
    r = ::getaddrinfo(host.empty() ? nullptr : host.c_str(), serv.c_str(), &hints, &out.list);
  if (r != 0)
    throw LineError("tcp " + endpoint(host, port) + ": cannot resolve: " +
                    (r == EAI_SYSTEM ? posix::error_text(errno) : ::gai_strerror(r)));
}

void set_nodelay(int fd) {
  // SAbus frames are a few bytes each; Nagle would hold them back.
  const int one = 1;
  (void)::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
}

}  // namespace

TcpLine::TcpLine(UniqueFd fd, std::string description)
    : FdLine(std::move(fd), Kind::socket), description_(std::move(description)) {}

bool TcpLine::peer_closed() const {
  pollfd p{fd(), POLLRDHUP, 0};
  if (::poll(&p, 1, 0) <= 0) return false;
  return (p.revents & (POLLRDHUP | POLLHUP | POLLERR)) != 0;
}

std::unique_ptr<TcpLine> TcpLine::connect(const std::string& host, std::uint16_t port,
                                          std::chrono::milliseconds timeout) {
  const std::string name = "tcp " + endpoint(host, port);
  AddrInfo ai;
  resolve(host, port, false, ai);
  const auto deadline = Clock::now() + timeout;
  std::string last_error = "no address";
  for (addrinfo* a = ai.list; a != nullptr; a = a->ai_next) {
    UniqueFd fd(::socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol));
    if (!fd) {
      last_error = posix::error_text(errno);
      continue;
    }
    int r = ::connect(fd.get(), a->ai_addr, a->ai_addrlen);
    // EINTR: the connection goes on in the background, as with EINPROGRESS.
    if (r != 0 && (errno == EINPROGRESS || errno == EINTR)) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
      const short rev = posix::poll_one(fd.get(), POLLOUT, std::max(left, std::chrono::milliseconds{0}));
      if (rev == 0) throw LineError(name + ": no connection within " + std::to_string(timeout.count()) + " ms");
      int err = 0;
      socklen_t len = sizeof err;
      if (::getsockopt(fd.get(), SOL_SOCKET, SO_ERROR, &err, &len) != 0) err = errno;
      r = err == 0 ? 0 : -1;
      errno = err;
    }
    if (r != 0) {
      last_error = posix::error_text(errno);
      continue;
    }
    set_nodelay(fd.get());
    return std::unique_ptr<TcpLine>(new TcpLine(std::move(fd), name));
  }
  throw LineError(name + ": cannot connect: " + last_error);
}

TcpListener::TcpListener(UniqueFd fd, std::string address, std::uint16_t port)
    : fd_(std::move(fd)), address_(std::move(address)), port_(port) {}

std::unique_ptr<TcpListener> TcpListener::listen(const std::string& host, std::uint16_t port) {
  AddrInfo ai;
  resolve(host, port, true, ai);
  std::string last_error = "no address";
  for (addrinfo* a = ai.list; a != nullptr; a = a->ai_next) {
    UniqueFd fd(::socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol));
    if (!fd) {
      last_error = posix::error_text(errno);
      continue;
    }
    // A restarted server may bind again while old connections sit in TIME_WAIT.
    const int one = 1;
    (void)::setsockopt(fd.get(), SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    // Clients that connect while one is being served wait in the backlog, as
    // at a device server's port; they are accepted in turn.
    if (::bind(fd.get(), a->ai_addr, a->ai_addrlen) != 0 || ::listen(fd.get(), 8) != 0) {
      last_error = posix::error_text(errno);
      continue;
    }
    sockaddr_storage sa{};
    socklen_t len = sizeof sa;
    if (::getsockname(fd.get(), reinterpret_cast<sockaddr*>(&sa), &len) != 0) {
      last_error = posix::error_text(errno);
      continue;
    }
    const std::string bound = address_text(sa);
    const auto actual = static_cast<std::uint16_t>(
        sa.ss_family == AF_INET6 ? ntohs(reinterpret_cast<const sockaddr_in6*>(&sa)->sin6_port)
                                 : ntohs(reinterpret_cast<const sockaddr_in*>(&sa)->sin_port));
    return std::unique_ptr<TcpListener>(new TcpListener(std::move(fd), bound, actual));
  }
  throw LineError("tcp " + endpoint(host, port) + ": cannot listen: " + last_error);
}

std::unique_ptr<TcpLine> TcpListener::accept(std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    const short rev = posix::poll_one(fd_.get(), POLLIN, std::max(left, std::chrono::milliseconds{0}));
    if (rev == 0) return nullptr;
    sockaddr_storage peer{};
    socklen_t len = sizeof peer;
    const int fd = ::accept4(fd_.get(), reinterpret_cast<sockaddr*>(&peer), &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd >= 0) {
      UniqueFd owned(fd);
      set_nodelay(fd);
      return std::unique_ptr<TcpLine>(
          new TcpLine(std::move(owned), "tcp " + address_ + " (client " + address_text(peer) + ")"));
    }
    // A client that gave up between poll() and accept(), or a signal: wait on.
    if (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK || errno == ECONNABORTED || errno == EPROTO) {
      if (Clock::now() >= deadline) return nullptr;
      continue;
    }
    throw LineError(describe() + ": accept failed: " + posix::error_text(errno));
  }
}

std::string TcpListener::describe() const { return "tcp " + address_ + " (listening)"; }

}  // namespace sabus::harness
