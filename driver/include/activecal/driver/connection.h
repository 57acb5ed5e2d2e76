// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The byte streams the driver protocol runs over: lines of text on a pair
// of file descriptors (a child process's stdin and stdout, or a TCP
// socket), read with a timeout.
//
//   std::unique_ptr<DriverConnection> c;
//   OpenDriverConnection("python3 my_driver.py --port=/dev/ttyUSB0", &c,
//                        &error);           // a child process, no shell
//   OpenDriverConnection("tcp://10.0.0.5:7000", &c, &error);  // running
//   c->channel().WriteLine(...); c->channel().ReadLine(30.0, &line, &error);
//
// A command is split into words as a POSIX shell would (quotes, backslash,
// $VARIABLES and ~ expanded) by wordexp(3) with command substitution off;
// it is then run directly (posix_spawnp, PATH searched), never by a shell:
// pipes, redirections and ';' are refused with a hint to ask for a shell
// ("sh -c '...'") explicitly. The child inherits stderr, so what the driver
// prints there reaches the user. Writing to a driver that has exited is an
// error ("Broken pipe"), never a SIGPIPE: the signal is blocked for each
// write and one it raised is consumed, so the process's own disposition of
// SIGPIPE is left alone (a program piped into `head` still ends with it).

#ifndef ACTIVECAL_DRIVER_CONNECTION_H_
#define ACTIVECAL_DRIVER_CONNECTION_H_

#include <sys/types.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace activecal {

// Lines over a read and a write file descriptor ('\n' ends a line; a '\r'
// before it is dropped). Not thread-safe.
class LineChannel {
 public:
  enum class ReadResult { kLine, kTimeout, kClosed, kError };

  // Takes ownership of the descriptors (closed by the destructor; the same
  // descriptor may be given twice, a socket).
  LineChannel(int read_fd, int write_fd);
  ~LineChannel();
  LineChannel(const LineChannel&) = delete;
  LineChannel& operator=(const LineChannel&) = delete;

  // The next line, waiting at most timeout_s seconds (<= 0: forever).
  // kClosed: the other side closed its end (an unfinished last line is
  // dropped); kError: *error says why (a line longer than 64 MB, a failed
  // read).
  ReadResult ReadLine(double timeout_s, std::string* line, std::string* error);
  // Writes `line` and a newline, all of it, or false with *error (the
  // other side has gone: "Broken pipe").
  bool WriteLine(const std::string& line, std::string* error);
  // Closes the write side (the other side then reads end of file).
  void CloseWrite();
  // Closes the read side (the other side's writes then fail: a driver
  // flooding its stdout ends); ReadLine then returns kClosed.
  void CloseRead();

 private:
  int read_fd_;
  int write_fd_;
  std::string buffer_;
  size_t scanned_ = 0;  // bytes of buffer_ known to hold no newline
};

// A running driver: a child process or a TCP connection.
class DriverConnection {
 public:
  virtual ~DriverConnection() = default;
  virtual LineChannel& channel() = 0;
  // "driver 'python3 d.py'" or "driver tcp://host:port", for messages.
  virtual std::string name() const = 0;
  // After the channel closed: why ("exited with status 3", "was killed by
  // signal 9", "closed the connection"), waiting up to wait_s seconds for
  // a child to finish exiting.
  virtual std::string WhyClosed(double wait_s) = 0;
  // Ends the connection: closes activecal's side (both pipes of a child),
  // waits up to wait_s seconds for a child to exit, then terminates it
  // (SIGTERM, then SIGKILL). Returns a note when it had to, else "".
  virtual std::string Shutdown(double wait_s) = 0;
};

// `spec` is "tcp://HOST:PORT" (a driver already listening) or a command.
// `connect_timeout_s` bounds the TCP connect. False with a one-line *error
// naming the spec and the cause.
bool OpenDriverConnection(const std::string& spec, double connect_timeout_s,
                          std::unique_ptr<DriverConnection>* connection,
                          std::string* error);

// Splits a command into words (wordexp, no command substitution); the
// error names what is refused.
bool SplitDriverCommand(const std::string& command,
                        std::vector<std::string>* words, std::string* error);

// The driver's side of TCP: a socket listening on `host` (e.g. 127.0.0.1,
// or 0.0.0.0 for every interface) and `port` (0: any free one).
class TcpListener {
 public:
  ~TcpListener();
  static bool Listen(const std::string& host, int port,
                     std::unique_ptr<TcpListener>* listener,
                     std::string* error);
  const std::string& host() const { return host_; }  // as given
  int port() const { return port_; }
  // Waits for the next client; its channel reads and writes the socket.
  bool Accept(std::unique_ptr<LineChannel>* channel, std::string* error);

 private:
  TcpListener(int fd, std::string host, int port)
      : fd_(fd), host_(std::move(host)), port_(port) {}
  int fd_;
  std::string host_;
  int port_;
};

}  // namespace activecal

#endif  // ACTIVECAL_DRIVER_CONNECTION_H_
