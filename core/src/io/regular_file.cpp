#include <tessera/regular_file.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace tessera {
namespace {

[[noreturn]] void not_regular(const std::string& path, unsigned mode) {
  throw std::runtime_error(path + " is " + file_kind_name(mode) + " (allowed: a regular file)");
}

}  // namespace

std::string file_kind_name(unsigned mode) {
  if (S_ISREG(mode)) return "a regular file";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

RegularFile::RegularFile(const std::string& path) : m_path(path) {
  // Opening a FIFO for reading with O_NONBLOCK returns at once instead of waiting for a writer
  m_fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (m_fd < 0 && errno == ENOENT) throw std::runtime_error(path + " does not exist");
  if (m_fd < 0) throw std::runtime_error(path + ": cannot open: " + std::strerror(errno));
  struct stat st {};
  if (::fstat(m_fd, &st) != 0) {
    const int err = errno;
    ::close(m_fd);
    throw std::runtime_error(path + ": cannot stat: " + std::strerror(err));
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(m_fd);
    m_fd = -1;
    not_regular(path, st.st_mode);
  }
  m_size = static_cast<std::uint64_t>(st.st_size);
}

RegularFile::~RegularFile() {
  if (m_fd >= 0) ::close(m_fd);
}

void RegularFile::read_at(std::uint64_t offset, void* out, std::size_t n) const {
  auto* p = static_cast<char*>(out);
  std::size_t done = 0;
  while (done < n) {
    const ssize_t r = ::pread(m_fd, p + done, n - done, static_cast<off_t>(offset + done));
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) {
      throw std::runtime_error(m_path + ": read failed after " + std::to_string(done) + " of " + std::to_string(n) +
                               " bytes: " + std::strerror(errno));
    }
    if (r == 0) {
      throw std::runtime_error(m_path + ": file ends after " + std::to_string(offset + done) +
                               " bytes, expected at least " + std::to_string(offset + n));
    }
    done += static_cast<std::size_t>(r);
  }
}

}  // namespace tessera
