#pragma once
/// Temporary files for atomic writes (write, then rename into place). The temporary name sits
/// beside the final one (same directory, so rename() is atomic) and is made new: created with
/// O_CREAT | O_EXCL | O_NOFOLLOW, so whatever already has the name (a FIFO, which would block
/// the writer, or a symbolic link, which would redirect it) is never opened; the next name is
/// tried instead.
#include <string>

namespace tessera {

/// Creates an empty regular file `path.tmp.<pid>.<n>` (the first n not taken, at most 100
/// tries) and returns its name; the caller writes it by name and renames or removes it.
/// Throws std::runtime_error naming the temporary file when it cannot be created.
std::string create_temp_file_beside(const std::string& path);

}  // namespace tessera
