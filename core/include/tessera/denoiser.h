#pragma once
/// Denoising with Intel Open Image Denoise (OIDN 2.x), loaded at run time with dlopen: the
/// build needs nothing of it, and a process that never denoises never loads it.
///
/// Where the library is looked for, first that loads wins (oidn_search_paths()). Only
/// absolute locations are searched: an empty or relative entry (the working directory) of PATH
/// or LD_LIBRARY_PATH, and a relative HOME, are passed over.
///   1. $TESSERA_OIDN_LIBRARY, an absolute path, when set and not empty; then ONLY that (a
///      wrong or relative path is an error naming it, never a silent fall-back to another
///      copy). Set but empty counts as unset, and the not-found message says "empty (ignored)";
///   2. the system's libOpenImageDenoise.so.2: first <dir>/libOpenImageDenoise.so.2 for each
///      absolute LD_LIBRARY_PATH entry that holds one, then, only when no LD_LIBRARY_PATH
///      entry holds one, a plain dlopen by soname (the loader cache, the system directories).
///      A relative or empty entry that holds one, or an entry with a loader token ($ORIGIN),
///      makes the plain dlopen skipped (the loader would go there unchecked);
///   3. the library inside the PyPI package `pyoidn` of the first `python3` in an absolute
///      PATH entry: <its dir>/../lib/python3*/site-packages/pyoidn/oidn/lib/ (a venv; the same
///      again from the directory the python3 link resolves to), then the user and system site
///      directories $HOME/.local/lib/python3*/site-packages and /usr/local/lib/python3*/dist-packages.
/// Every path is checked right before dlopen to be a regular file, without blocking
/// (RegularFile: O_NONBLOCK open, fstat): a FIFO, a terminal, a device, a socket or a
/// directory is refused, naming the path and its kind, instead of blocking dlopen. The check
/// and the load open the name twice: a file swapped in between (by someone who can write that
/// directory) is not caught, and the libraries OIDN itself loads (its core library, TBB) are
/// the loader's to find.
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
/// (globs expanded; a path that does not exist is left out, except the one of step 1 and the
/// bare soname of step 2). Nothing is opened or loaded.
std::vector<std::string> oidn_search_paths();

/// Loads OIDN if not yet done; throws DenoiserUnavailable if it cannot be loaded or is not
/// OIDN 2.x (a library without OIDN's C functions). Returns the path that was loaded.
std::string require_denoiser();

/// Denoises img's RGB (HDR, linear) with OIDN's "RT" filter, guided by img.albedo and, when
/// any normal is non-zero, img.normal (both optional, width*height*3). Fills img.denoised
/// (width*height*3); rgba is left untouched. Runs on OIDN's CPU device with `threads` threads
/// (0 = as many as the caller's TBB arena has, as RenderOptions::threads; OIDN takes at most
/// the hardware threads), never pinned to cores (an MPI launcher binds each rank to its cores:
/// OIDN's own pinning would put every rank's threads on the same ones). The device is created
/// once per process and again only when another thread count is asked for; calls are
/// serialised by a lock. Throws DenoiserUnavailable as require_denoiser(), std::runtime_error
/// with OIDN's message if the device or the filter fails.
void denoise(Image& img, int threads = 0);

/// The threads OIDN's CPU device runs on, as OIDN reports them for the device the last
/// denoise() made; 0 before the first.
int denoiser_threads();

}  // namespace tessera
