#pragma once
/// Opening input files that must be regular files. A FIFO, a device (/dev/zero), a socket or a
/// directory given where a data file is expected would block forever or never end; they are
/// refused before anything is read. The check is race-free: the file is opened with O_NONBLOCK
/// (so opening a FIFO does not wait for a writer) and the type is taken from the open
/// descriptor (fstat), not from the name.
#include <cstdint>
#include <string>

namespace tessera {

/// A read-only descriptor of a regular file, closed by the destructor. Not copyable.
class RegularFile {
 public:
  /// Throws std::runtime_error "PATH does not exist", "PATH: cannot open: <errno text>" or
  /// "PATH is a FIFO (allowed: a regular file)" (directory, character device, block device,
  /// socket likewise).
  explicit RegularFile(const std::string& path);
  ~RegularFile();
  RegularFile(const RegularFile&) = delete;
  RegularFile& operator=(const RegularFile&) = delete;

  int fd() const { return m_fd; }
  /// Size in bytes at open time.
  std::uint64_t size() const { return m_size; }
  const std::string& path() const { return m_path; }
  /// Reads exactly `n` bytes at `offset`; throws naming the path when the file is shorter or
  /// the read fails.
  void read_at(std::uint64_t offset, void* out, std::size_t n) const;

 private:
  std::string m_path;
  int m_fd = -1;
  std::uint64_t m_size = 0;
};

/// What a stat mode is, for messages: "a FIFO", "a directory", "a character device", ...
std::string file_kind_name(unsigned mode);

}  // namespace tessera
