#pragma once
/// Denoising with Intel Open Image Denoise (OIDN 2.x), loaded at run time with dlopen: the
/// build needs nothing of it, and a process that never denoises never loads it.
///
/// Where the library is looked for, first that loads wins (oidn_search_paths()):
///   1. $TESSERA_OIDN_LIBRARY, a path, when set and not empty; then ONLY that (a wrong path
///      is an error naming it, never a silent fall-back to another copy);
///   2. the system's libOpenImageDenoise.so.2 (plain dlopen by soname: LD_LIBRARY_PATH,
///      the loader cache);
///   3. the library inside the PyPI package `pyoidn` of the first `python3` on PATH:
///      <its dir>/../lib/python3*/site-packages/pyoidn/oidn/lib/ (a venv; the same again
///      from the directory the python3 link resolves to), then the user and system site
///      directories ~/.local/lib/python3*/site-packages and /usr/local/lib/python3*/dist-packages.
/// No subprocess is run (fork is unsafe inside MPI simulations).
///
/// The library is loaded once per process (thread-safe); the outcome, success or failure, is
/// kept for the life of the process. pyoidn ships its own libtbb.so.12: the dynamic loader
/// binds OIDN to the libtbb.so.12 this process already has (Debian's TBB 2021.8 exports
/// every TBB symbol OIDN 2.5's CPU device uses), so one TBB runs both.
#include <tessera/image.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace tessera {

/// The denoiser was asked for and cannot be loaded. The message names every place tried
/// (and why each failed) and how to install it.
class DenoiserUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The candidate library paths of the lookup above, in order, for the current environment
/// (globs expanded; a path that does not exist is left out, except the ones of steps 1 and 2).
std::vector<std::string> oidn_search_paths();

/// Loads OIDN if not yet done; throws DenoiserUnavailable if it cannot be loaded or is not
/// OIDN 2.x (a library without OIDN's C functions). Returns the path that was loaded.
std::string require_denoiser();

/// Denoises img's RGB (HDR, linear) with OIDN's "RT" filter, guided by img.albedo and, when
/// any normal is non-zero, img.normal (both optional, width*height*3). Fills img.denoised
/// (width*height*3); rgba is left untouched. Runs on OIDN's CPU device (created once per
/// process, calls serialised by a lock). Throws DenoiserUnavailable as require_denoiser(),
/// std::runtime_error with OIDN's message if the filter fails.
void denoise(Image& img);

}  // namespace tessera
