#include <tessera/atomic_output.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <climits>
#include <cstring>
#include <mutex>

namespace tessera {
namespace {

/// The test hook's fault (detail::set_write_fault); UINT64_MAX: none
struct WriteFault {
  std::mutex mutex;
  std::uint64_t byte = UINT64_MAX;
  int error = 0;
  std::string path_suffix;
};
WriteFault& write_fault() {
  static WriteFault fault;
  return fault;
}
std::atomic<bool> g_fault_set{false};  ///< fast path: no lock while no fault was ever set

/// A file name next to `path`, unique within this process and across processes.
std::string temp_path_for(const std::string& path) {
  static std::atomic<unsigned long> counter{0};
  return path + ".tmp." + std::to_string(static_cast<long>(::getpid())) + "." +
         std::to_string(counter.fetch_add(1, std::memory_order_relaxed));
}

std::string errno_text(int error) { return std::strerror(error); }

/// The path as shown in messages: a NUL made visible.
std::string shown(const std::string& path) {
  std::string s;
  for (const char c : path) s += c == '\0' ? std::string("\\x00") : std::string(1, c);
  return s;
}

}  // namespace

AtomicOutputError::AtomicOutputError(const std::string& path, const std::string& fault)
    : std::runtime_error("cannot write '" + shown(path) + "': " + fault), m_fault(fault) {}

AtomicOutputFile::AtomicOutputFile(const std::string& path) : m_path(path) {
  if (path.empty() || path.find('\0') != std::string::npos)
    throw AtomicOutputError(path, "the path is empty or contains a NUL character");
  if (g_fault_set.load(std::memory_order_acquire)) {
    WriteFault& f = write_fault();
    const std::lock_guard<std::mutex> lock(f.mutex);
    m_fault_armed = f.byte != UINT64_MAX && path.size() >= f.path_suffix.size() &&
                    path.compare(path.size() - f.path_suffix.size(), f.path_suffix.size(), f.path_suffix) == 0;
    if (m_fault_armed) {
      m_fault_byte = f.byte;
      m_fault_errno = f.error;
    }
  }
  // A fresh file: a leftover of a killed process with a reused pid is skipped, never opened
  for (int attempt = 0; attempt < 100 && m_fd < 0; ++attempt) {
    m_temp = temp_path_for(path);
    do {
      m_fd = ::open(m_temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC | O_NOCTTY, 0666);
    } while (m_fd < 0 && errno == EINTR);
    if (m_fd < 0 && errno != EEXIST) break;
  }
  if (m_fd < 0) {
    const int error = errno;
    throw AtomicOutputError(path, "cannot create the temporary file '" + m_temp + "': " + errno_text(error));
  }
}

AtomicOutputFile::~AtomicOutputFile() { discard(); }

void AtomicOutputFile::discard() noexcept {
  if (m_fd < 0) return;
  ::close(m_fd);  // the file is thrown away: its close status does not matter
  m_fd = -1;
  ::unlink(m_temp.c_str());
}

void AtomicOutputFile::fail(const std::string& fault) {
  if (m_first_fault.empty()) m_first_fault = fault;
  throw AtomicOutputError(m_path, fault);
}

void AtomicOutputFile::write(const void* data, std::size_t n) { write_at(m_size, data, n); }

void AtomicOutputFile::write_at(std::uint64_t offset, const void* data, std::size_t n) {
  if (m_fd < 0) fail("the file was already committed");
  if (!m_first_fault.empty()) fail(m_first_fault);
  if (offset > std::uint64_t(LLONG_MAX) - n) fail("byte offset " + std::to_string(offset) + " is too large");
  const auto* bytes = static_cast<const unsigned char*>(data);
  std::size_t done = 0;
  while (done < n) {
    const std::uint64_t at = offset + done;
    std::size_t chunk = std::min<std::size_t>(n - done, std::size_t(1) << 30);

    // Test hook: stop at the injected byte as a full disk would
    int error = 0;
    if (m_fault_armed && at + chunk > m_fault_byte) {
      if (at >= m_fault_byte) error = m_fault_errno;
      else chunk = static_cast<std::size_t>(m_fault_byte - at);
    }

    // One pwrite: a short count continues, EINTR retries, anything else is the fault
    ssize_t w = -1;
    if (error == 0) {
      w = ::pwrite(m_fd, bytes + done, chunk, static_cast<off_t>(at));
      if (w < 0) error = errno;
      if (w < 0 && error == EINTR) continue;
      if (w == 0) error = ENOSPC;  // no progress on a regular file: treat as full
    }
    if (error != 0)
      fail("write failed at byte " + std::to_string(at) + " of the temporary file '" + m_temp +
           "': " + errno_text(error));
    done += static_cast<std::size_t>(w);
    m_size = std::max(m_size, offset + done);
  }
}

void AtomicOutputFile::commit() {
  if (m_fd < 0) fail("the file was already committed");
  try {
    if (!m_first_fault.empty()) fail(m_first_fault);

    // Verify: the file holds exactly the bytes written
    struct stat st {};
    if (::fstat(m_fd, &st) != 0) fail("cannot stat the temporary file '" + m_temp + "': " + errno_text(errno));
    if (std::uint64_t(st.st_size) != m_size)
      fail("the temporary file '" + m_temp + "' has " + std::to_string(st.st_size) + " bytes after " +
           std::to_string(m_size) + " were written");

    // Close, checked: some file systems report a deferred write error only here
    const int fd = m_fd;
    m_fd = -1;
    if (::close(fd) != 0 && errno != EINTR) {
      const int error = errno;
      ::unlink(m_temp.c_str());
      fail("closing the temporary file '" + m_temp + "' failed: " + errno_text(error));
    }
    if (::rename(m_temp.c_str(), m_path.c_str()) != 0) {
      const int error = errno;
      ::unlink(m_temp.c_str());
      fail("cannot rename the temporary file '" + m_temp + "' into place: " + errno_text(error));
    }
  } catch (...) {
    discard();
    throw;
  }
}

void write_file_atomically(const std::string& path, std::string_view bytes) {
  AtomicOutputFile out(path);
  out.write(bytes);
  out.commit();
}

namespace detail {
void set_write_fault(std::uint64_t byte, int error, const std::string& path_suffix) {
  WriteFault& f = write_fault();
  const std::lock_guard<std::mutex> lock(f.mutex);
  f.byte = byte;
  f.error = error;
  f.path_suffix = path_suffix;
  g_fault_set.store(true, std::memory_order_release);
}
void clear_write_fault() noexcept {
  WriteFault& f = write_fault();
  const std::lock_guard<std::mutex> lock(f.mutex);
  f.byte = UINT64_MAX;
}
}  // namespace detail

}  // namespace tessera
