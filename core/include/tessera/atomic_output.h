#pragma once
/// AtomicOutputFile: the one way Tessera writes a file (EXR, PNG, Cinema data.csv, the effective
/// config, statistics, raw volumes). Either the complete file appears under its final name, or
/// nothing changes there: a full disk, a quota, a file-size limit or an I/O error mid-write
/// throws, removes the temporary file and leaves an older file under the final name untouched.
///
/// How: the bytes go to a fresh temporary file `<path>.tmp.<pid>.<n>` in the same directory
/// (O_EXCL, so never someone else's file; the same file system, so the rename is atomic).
/// Every write() result is checked (short writes continued, EINTR retried, anything else
/// thrown with the byte offset and strerror). commit() then checks the file size against the
/// bytes written, checks close() (NFS and quotas can report a failure only there) and renames
/// the file into place. No fsync: this protects against a failed write and a crashed or killed
/// process, not against power loss (in-situ output often sits on a parallel file system where
/// an fsync per frame is expensive).
///
/// While alive, the object holds BlockWriteSignals (signal_guard.h), so a file-size limit is
/// EFBIG and a closed pipe EPIPE, never a signal. Not thread-safe; create, write and commit on
/// one thread.
#include <tessera/signal_guard.h>

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

namespace tessera {

/// Thrown by AtomicOutputFile. what() is "cannot write '<path>': <fault>"; fault() is the part
/// after the path (the offset and strerror, or what the check found), for callers that add
/// their own prefix.
class AtomicOutputError : public std::runtime_error {
 public:
  AtomicOutputError(const std::string& path, const std::string& fault);
  const std::string& fault() const noexcept { return m_fault; }

 private:
  std::string m_fault;
};

class AtomicOutputFile {
 public:
  /// Creates the temporary file next to `path` (mode 0666 less the umask). Throws
  /// AtomicOutputError if it cannot (missing directory, permissions, a NUL in the name).
  explicit AtomicOutputFile(const std::string& path);
  /// Without a successful commit(): closes and removes the temporary file; `path` untouched.
  ~AtomicOutputFile();
  AtomicOutputFile(const AtomicOutputFile&) = delete;
  AtomicOutputFile& operator=(const AtomicOutputFile&) = delete;

  /// Appends `n` bytes after the furthest byte written so far.
  void write(const void* data, std::size_t n);
  void write(std::string_view bytes) { write(bytes.data(), bytes.size()); }
  /// Writes `n` bytes at `offset` (a streaming writer that seeks back to fill in a table).
  /// A gap left unwritten below size() reads as zeros.
  void write_at(std::uint64_t offset, const void* data, std::size_t n);
  /// One past the furthest byte written.
  std::uint64_t size() const noexcept { return m_size; }

  /// Checks the file size == size(), closes (checked) and renames onto the final path. After
  /// any failed write, commit() throws that first fault again (a writer that swallowed the
  /// exception still cannot publish a truncated file). Throws AtomicOutputError; then the
  /// temporary file is gone and the final path untouched.
  void commit();

  const std::string& path() const noexcept { return m_path; }
  /// The temporary file, e.g. for a format check before commit().
  const std::string& temp_path() const noexcept { return m_temp; }

 private:
  [[noreturn]] void fail(const std::string& fault);
  void discard() noexcept;

  BlockWriteSignals m_no_signals;
  std::string m_path, m_temp;
  int m_fd = -1;
  std::uint64_t m_size = 0;
  std::string m_first_fault;   ///< non-empty after a failed write
  bool m_fault_armed = false;  ///< detail::set_write_fault applies to this file
  std::uint64_t m_fault_byte = 0;
  int m_fault_errno = 0;
};

/// Writes `bytes` to `path` through an AtomicOutputFile (parent directory must exist).
void write_file_atomically(const std::string& path, std::string_view bytes);

namespace detail {
/// Test hook: in every AtomicOutputFile created afterwards whose final path ends with
/// `path_suffix` ("" = every file), a write that reaches byte offset `byte` writes the bytes
/// before it, then fails with `error` (e.g. ENOSPC) as if write() had returned it.
/// Process-wide; clear_write_fault() turns it off. Not for production use.
void set_write_fault(std::uint64_t byte, int error, const std::string& path_suffix = "");
void clear_write_fault() noexcept;
}  // namespace detail

}  // namespace tessera
