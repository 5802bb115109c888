#pragma once
/// Probing a caller's host array before anything reads it, so that a pointer to freed or
/// unmapped memory is an error naming the array instead of a segmentation fault in the
/// simulation (the adapter's field arrays, docs/insitu.md).
#include <cstddef>
#include <cstdint>
#include <optional>

namespace tessera {

/// Probes [p, p + bytes) with process_vm_readv on this process, which reports a read it
/// cannot make instead of faulting: the first and last byte and up to 62 bytes evenly spaced
/// between. Returns the offset from `p` of the first probed byte that cannot be read, or
/// nullopt when every probed byte reads, when `bytes` is 0, or when the system refuses the
/// probe itself (no such system call, or a seccomp filter: then nothing is known and nothing
/// is claimed). It finds an array that was freed back to the system (unmapped), one that runs
/// past the end of its mapping, and memory without host access (a freed cudaMalloc pointer:
/// its address range has no host pages); not a hole inside an array of more than 64 pages,
/// nor memory that is mapped but belongs to something else. One system call, no allocation.
std::optional<std::uint64_t> unreadable_byte(const void* p, std::size_t bytes);

}  // namespace tessera
