// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/driver/connection.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>
#include <wordexp.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <thread>

#include "activecal/io/sigpipe_block.h"

extern char** environ;

namespace activecal {

namespace {

constexpr size_t kMaxLineBytes = size_t{64} << 20;

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
      .count();
}

// write(2) that cannot raise SIGPIPE (SigpipeBlock): a driver that has gone
// is an EPIPE while the process's disposition of SIGPIPE stays its own
// (activecal_active | head still ends activecal when head exits). The write
// may also return a part written and raise SIGPIPE (the reader left during
// it): the block takes it off whatever the write returned.
ssize_t WriteWithoutSigpipe(int fd, const char* data, size_t size) {
  const SigpipeBlock block;
  return write(fd, data, size);
}

// Milliseconds for poll(2), at most INT_MAX.
int PollMs(double seconds) {
  const double ms = std::ceil(seconds * 1000);
  return ms >= std::numeric_limits<int>::max() ? std::numeric_limits<int>::max()
                                               : static_cast<int>(ms);
}

std::string Errno() { return std::strerror(errno); }

class ProcessConnection : public DriverConnection {
 public:
  ProcessConnection(std::string command, pid_t pid, int read_fd, int write_fd)
      : command_(std::move(command)),
        pid_(pid),
        channel_(new LineChannel(read_fd, write_fd)) {}
  ~ProcessConnection() override {
    if (pid_ > 0) Shutdown(1.0);
  }
  LineChannel& channel() override { return *channel_; }
  std::string name() const override { return "driver '" + command_ + "'"; }

  std::string WhyClosed(double wait_s) override {
    if (pid_ <= 0) return Describe();
    const auto start = std::chrono::steady_clock::now();
    do {
      if (Reap(WNOHANG)) return Describe();
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    } while (SecondsSince(start) < wait_s);
    return "closed its stdout (the process still runs)";
  }

  std::string Shutdown(double wait_s) override {
    // Both ends: a driver blocked writing (a flood) then ends too.
    channel_->CloseWrite();
    channel_->CloseRead();
    if (pid_ <= 0) return "";
    const auto start = std::chrono::steady_clock::now();
    while (SecondsSince(start) < wait_s) {
      if (Reap(WNOHANG)) return "";
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (Reap(WNOHANG)) return "";
    kill(pid_, SIGTERM);
    const auto term = std::chrono::steady_clock::now();
    while (SecondsSince(term) < 1.0) {
      if (Reap(WNOHANG)) return name() + " did not exit; terminated it";
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    kill(pid_, SIGKILL);
    Reap(0);
    return name() + " did not exit; killed it";
  }

 private:
  // True when the child has exited (its status kept).
  bool Reap(int flags) {
    int status = 0;
    pid_t r;
    do {
      r = waitpid(pid_, &status, flags);
    } while (r < 0 && errno == EINTR);
    if (r == pid_ || (r < 0 && errno == ECHILD)) {
      if (r == pid_) status_ = status;
      pid_ = -1;
      return true;
    }
    return false;
  }
  std::string Describe() const {
    if (WIFEXITED(status_)) {
      return "exited with status " + std::to_string(WEXITSTATUS(status_));
    }
    if (WIFSIGNALED(status_)) {
      return "was killed by signal " + std::to_string(WTERMSIG(status_)) +
             " (" + strsignal(WTERMSIG(status_)) + ")";
    }
    return "exited";
  }

  std::string command_;
  pid_t pid_;
  int status_ = 0;
  std::unique_ptr<LineChannel> channel_;
};

class TcpConnection : public DriverConnection {
 public:
  TcpConnection(std::string spec, int fd)
      : spec_(std::move(spec)), channel_(new LineChannel(fd, fd)) {}
  LineChannel& channel() override { return *channel_; }
  std::string name() const override { return "driver " + spec_; }
  std::string WhyClosed(double) override { return "closed the connection"; }
  std::string Shutdown(double) override {
    channel_->CloseWrite();
    return "";
  }

 private:
  std::string spec_;
  std::unique_ptr<LineChannel> channel_;
};

bool SpawnDriver(const std::string& command,
                 std::unique_ptr<DriverConnection>* connection,
                 std::string* error) {
  std::vector<std::string> words;
  if (!SplitDriverCommand(command, &words, error)) return false;
  int to_child[2], from_child[2];
  if (pipe2(to_child, O_CLOEXEC) != 0) {
    *error = "--driver: pipe: " + Errno();
    return false;
  }
  if (pipe2(from_child, O_CLOEXEC) != 0) {
    *error = "--driver: pipe: " + Errno();
    close(to_child[0]);
    close(to_child[1]);
    return false;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, to_child[0], STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&actions, from_child[1], STDOUT_FILENO);
  // The child starts with SIGPIPE at its default, whatever activecal did.
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t defaults;
  sigemptyset(&defaults);
  sigaddset(&defaults, SIGPIPE);
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF);
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int rc =
      posix_spawnp(&pid, argv[0], &actions, &attributes, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  close(to_child[0]);
  close(from_child[1]);
  if (rc != 0) {
    close(to_child[1]);
    close(from_child[0]);
    *error = "--driver: cannot start '" + words[0] + "': " + std::strerror(rc);
    return false;
  }
  connection->reset(
      new ProcessConnection(command, pid, from_child[0], to_child[1]));
  return true;
}

bool ConnectTcp(const std::string& spec, double timeout_s,
                std::unique_ptr<DriverConnection>* connection,
                std::string* error) {
  std::string rest = spec.substr(6);  // after tcp://
  std::string host, port;
  if (!rest.empty() && rest[0] == '[') {
    const size_t close = rest.find(']');
    if (close != std::string::npos && close + 1 < rest.size() &&
        rest[close + 1] == ':') {
      host = rest.substr(1, close - 1);
      port = rest.substr(close + 2);
    }
  } else {
    const size_t colon = rest.rfind(':');
    if (colon != std::string::npos) {
      host = rest.substr(0, colon);
      port = rest.substr(colon + 1);
    }
  }
  if (host.empty() || port.empty() ||
      port.find_first_not_of("0123456789") != std::string::npos) {
    *error = "--driver: '" + spec +
             "' is not tcp://HOST:PORT (e.g. tcp://127.0.0.1:7000)";
    return false;
  }
  // A port is 16 bits: 70000 is refused, not taken modulo 65536.
  if (port.size() > 5 || std::stoi(port) < 1 || std::stoi(port) > 65535) {
    *error = "--driver: " + spec + ": the port must be in 1..65535, got '" +
             port + "'";
    return false;
  }
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* addresses = nullptr;
  const int gai = getaddrinfo(host.c_str(), port.c_str(), &hints, &addresses);
  if (gai != 0) {
    *error = "--driver: " + spec + ": " + gai_strerror(gai);
    return false;
  }
  std::string why = "no address";
  int fd = -1;
  for (addrinfo* a = addresses; a != nullptr && fd < 0; a = a->ai_next) {
    fd = socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC | SOCK_NONBLOCK,
                a->ai_protocol);
    if (fd < 0) {
      why = Errno();
      continue;
    }
    int rc = connect(fd, a->ai_addr, a->ai_addrlen);
    if (rc != 0 && errno == EINPROGRESS) {
      pollfd p{fd, POLLOUT, 0};
      const int ms = timeout_s > 0 ? PollMs(timeout_s) : -1;
      do {
        rc = poll(&p, 1, ms);
      } while (rc < 0 && errno == EINTR);
      if (rc == 0) {
        why = "no answer within " + std::to_string(timeout_s) + " s";
        rc = -1;
      } else if (rc > 0) {
        int err = 0;
        socklen_t len = sizeof(err);
        getsockopt(fd, SOL_SOCKET, SO_ERROR, &err, &len);
        if (err == 0) {
          rc = 0;
        } else {
          why = std::strerror(err);
          rc = -1;
        }
      } else {
        why = Errno();
      }
    } else if (rc != 0) {
      why = Errno();
    }
    if (rc != 0) {
      close(fd);
      fd = -1;
    }
  }
  freeaddrinfo(addresses);
  if (fd < 0) {
    *error = "--driver: cannot connect to " + spec + ": " + why;
    return false;
  }
  fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  connection->reset(new TcpConnection(spec, fd));
  return true;
}

}  // namespace

LineChannel::LineChannel(int read_fd, int write_fd)
    : read_fd_(read_fd), write_fd_(write_fd) {}

LineChannel::~LineChannel() {
  if (read_fd_ >= 0) close(read_fd_);
  if (write_fd_ >= 0 && write_fd_ != read_fd_) close(write_fd_);
}

void LineChannel::CloseRead() {
  if (read_fd_ < 0) return;
  if (read_fd_ == write_fd_) {
    shutdown(read_fd_, SHUT_RD);  // a socket still written to
  } else {
    close(read_fd_);
    read_fd_ = -1;
  }
}

void LineChannel::CloseWrite() {
  if (write_fd_ < 0) return;
  if (write_fd_ == read_fd_) {
    shutdown(write_fd_, SHUT_WR);
  } else {
    close(write_fd_);
  }
  write_fd_ = -1;
}

LineChannel::ReadResult LineChannel::ReadLine(double timeout_s,
                                              std::string* line,
                                              std::string* error) {
  const auto start = std::chrono::steady_clock::now();
  for (;;) {
    // Only what came since the last look is searched (a long line is not
    // scanned again for every chunk).
    const size_t end = buffer_.find('\n', scanned_);
    if (end != std::string::npos) {
      *line = buffer_.substr(0, end);
      buffer_.erase(0, end + 1);
      scanned_ = 0;
      if (!line->empty() && line->back() == '\r') line->pop_back();
      return ReadResult::kLine;
    }
    scanned_ = buffer_.size();
    if (read_fd_ < 0) return ReadResult::kClosed;
    if (buffer_.size() > kMaxLineBytes) {
      *error = "a line longer than " + std::to_string(kMaxLineBytes >> 20) +
               " MB without a newline";
      return ReadResult::kError;
    }
    int ms = -1;
    if (timeout_s > 0) {
      const double left = timeout_s - SecondsSince(start);
      if (left <= 0) return ReadResult::kTimeout;
      ms = PollMs(left);
    }
    pollfd p{read_fd_, POLLIN, 0};
    const int rc = poll(&p, 1, ms);
    if (rc < 0) {
      if (errno == EINTR) continue;
      *error = "poll: " + Errno();
      return ReadResult::kError;
    }
    if (rc == 0) continue;  // the deadline is checked above
    char chunk[65536];
    const ssize_t n = read(read_fd_, chunk, sizeof(chunk));
    if (n < 0) {
      if (errno == EINTR || errno == EAGAIN) continue;
      if (errno == ECONNRESET) return ReadResult::kClosed;
      *error = "read: " + Errno();
      return ReadResult::kError;
    }
    if (n == 0) return ReadResult::kClosed;
    buffer_.append(chunk, static_cast<size_t>(n));
  }
}

bool LineChannel::WriteLine(const std::string& line, std::string* error) {
  if (write_fd_ < 0) {
    *error = "the channel is closed for writing";
    return false;
  }
  const std::string text = line + "\n";
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n =
        WriteWithoutSigpipe(write_fd_, text.data() + done, text.size() - done);
    if (n < 0) {
      if (errno == EINTR || errno == EAGAIN) continue;
      *error = Errno();
      return false;
    }
    done += static_cast<size_t>(n);
  }
  return true;
}

bool SplitDriverCommand(const std::string& command,
                        std::vector<std::string>* words, std::string* error) {
  words->clear();
  wordexp_t w;
  const int rc = wordexp(command.c_str(), &w, WRDE_NOCMD);
  if (rc != 0) {
    switch (rc) {
      case WRDE_BADCHAR:
        *error =
            "--driver: '" + command +
            "' holds a character only a shell understands (| & ; < > ( ) { "
            "} or a newline): activecal runs the command without a shell; "
            "quote the character, or ask for a shell: --driver=\"sh -c "
            "'...'\"";
        break;
      case WRDE_CMDSUB:
        *error = "--driver: '" + command +
                 "': command substitution ($(...) or `...`) is not run";
        break;
      case WRDE_SYNTAX:
        *error = "--driver: '" + command + "': unbalanced quotes";
        break;
      default:
        *error = "--driver: '" + command + "' cannot be split into words";
    }
    if (rc == WRDE_NOSPACE) wordfree(&w);
    return false;
  }
  for (size_t i = 0; i < w.we_wordc; ++i) words->push_back(w.we_wordv[i]);
  wordfree(&w);
  if (words->empty()) {
    *error = "--driver: the command is empty";
    return false;
  }
  return true;
}

bool OpenDriverConnection(const std::string& spec, double connect_timeout_s,
                          std::unique_ptr<DriverConnection>* connection,
                          std::string* error) {
  if (spec.rfind("tcp://", 0) == 0) {
    return ConnectTcp(spec, connect_timeout_s, connection, error);
  }
  return SpawnDriver(spec, connection, error);
}

TcpListener::~TcpListener() {
  if (fd_ >= 0) close(fd_);
}

bool TcpListener::Listen(const std::string& host, int port,
                         std::unique_ptr<TcpListener>* listener,
                         std::string* error) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  addrinfo* addresses = nullptr;
  const std::string service = std::to_string(port);
  const int gai = getaddrinfo(host.empty() ? nullptr : host.c_str(),
                              service.c_str(), &hints, &addresses);
  if (gai != 0) {
    *error = "listen on " + host + ":" + service + ": " + gai_strerror(gai);
    return false;
  }
  std::string why = "no address";
  int fd = -1;
  for (addrinfo* a = addresses; a != nullptr && fd < 0; a = a->ai_next) {
    fd = socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) {
      why = Errno();
      continue;
    }
    const int one = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
    if (bind(fd, a->ai_addr, a->ai_addrlen) != 0 || listen(fd, 4) != 0) {
      why = Errno();
      close(fd);
      fd = -1;
    }
  }
  freeaddrinfo(addresses);
  if (fd < 0) {
    *error = "listen on " + host + ":" + service + ": " + why;
    return false;
  }
  sockaddr_storage bound{};
  socklen_t len = sizeof(bound);
  getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &len);
  int bound_port = port;
  if (bound.ss_family == AF_INET) {
    bound_port = ntohs(reinterpret_cast<sockaddr_in*>(&bound)->sin_port);
  } else if (bound.ss_family == AF_INET6) {
    bound_port = ntohs(reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port);
  }
  listener->reset(new TcpListener(fd, host, bound_port));
  return true;
}

bool TcpListener::Accept(std::unique_ptr<LineChannel>* channel,
                         std::string* error) {
  int fd;
  do {
    fd = accept4(fd_, nullptr, nullptr, SOCK_CLOEXEC);
  } while (fd < 0 && errno == EINTR);
  if (fd < 0) {
    *error = "accept: " + Errno();
    return false;
  }
  channel->reset(new LineChannel(fd, fd));
  return true;
}

}  // namespace activecal
