#include <tessera/host_readable.h>

#include <sys/uio.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>

namespace tessera {

std::optional<std::uint64_t> unreadable_byte(const void* p, std::size_t bytes) {
  if (bytes == 0) return std::nullopt;
  constexpr std::size_t kProbes = 64;
  const std::size_t n = bytes < kProbes ? bytes : kProbes;
  std::uint64_t offset[kProbes];
  char sink[kProbes];
  iovec local[kProbes], remote[kProbes];
  const auto base = reinterpret_cast<std::uintptr_t>(p);
  const std::uint64_t last = bytes - 1;
  for (std::size_t i = 0; i < n; ++i) {
    // i (bytes - 1) / (n - 1) without overflow: bytes - 1 < 2^64 and i < 64
    offset[i] = n == 1 ? 0 : last / (n - 1) * i + last % (n - 1) * i / (n - 1);
    local[i] = {&sink[i], 1};
    remote[i] = {reinterpret_cast<void*>(base + offset[i]), 1};
  }
  const ssize_t r = process_vm_readv(getpid(), local, n, remote, n, 0);
  if (r == static_cast<ssize_t>(n)) return std::nullopt;
  if (r >= 0) return offset[r];  // partial: the probes stop at the first byte they cannot read
  if (errno == EFAULT) return offset[0];
  return std::nullopt;  // ENOSYS, EPERM, ...: the probe itself is refused
}

}  // namespace tessera
