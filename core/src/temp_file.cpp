#include <tessera/temp_file.h>

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace tessera {

std::string create_temp_file_beside(const std::string& path) {
  static std::atomic<unsigned long> counter{0};
  constexpr int kTries = 100;
  std::string tmp;
  for (int i = 0; i < kTries; ++i) {
    tmp = path + ".tmp." + std::to_string(static_cast<long>(::getpid())) + "." +
          std::to_string(counter.fetch_add(1, std::memory_order_relaxed));
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      return tmp;
    }
    if (errno != EEXIST) throw std::runtime_error("cannot create '" + tmp + "': " + std::strerror(errno));
  }
  throw std::runtime_error("cannot create a temporary file: " + std::to_string(kTries) +
                           " names beside it are taken, the last '" + tmp + "'");
}

}  // namespace tessera
