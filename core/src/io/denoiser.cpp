/// Open Image Denoise through dlopen: the lookup of denoiser.h, the few C functions used
/// (declared here from OIDN 2.x's public C API, include/OpenImageDenoise/oidn.h), one CPU
/// device per process.
#include <tessera/denoiser.h>
#include <tessera/memory_estimate.h>
#include <tessera/regular_file.h>

#include <tbb/task_arena.h>

#include <dlfcn.h>
#include <glob.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <system_error>
#include <type_traits>

namespace tessera {
namespace {

// ---- The subset of OIDN's C API used here (values as in oidn.h) ----
using OIDNDevice = void*;
using OIDNFilter = void*;
constexpr int kOidnDeviceTypeCpu = 1;  // OIDN_DEVICE_TYPE_CPU
constexpr int kOidnFormatFloat3 = 3;   // OIDN_FORMAT_FLOAT3
constexpr int kOidnErrorNone = 0;      // OIDN_ERROR_NONE

struct OidnApi {
  OIDNDevice (*newDevice)(int type) = nullptr;
  void (*commitDevice)(OIDNDevice) = nullptr;
  int (*getDeviceError)(OIDNDevice, const char** message) = nullptr;
  int (*getDeviceInt)(OIDNDevice, const char* name) = nullptr;
  void (*setDeviceInt)(OIDNDevice, const char* name, int value) = nullptr;
  void (*setDeviceBool)(OIDNDevice, const char* name, bool value) = nullptr;
  void (*releaseDevice)(OIDNDevice) = nullptr;
  OIDNFilter (*newFilter)(OIDNDevice, const char* type) = nullptr;
  void (*setSharedFilterImage)(OIDNFilter, const char* name, void* ptr, int format, std::size_t width,
                               std::size_t height, std::size_t byte_offset, std::size_t pixel_stride,
                               std::size_t row_stride) = nullptr;
  void (*setFilterBool)(OIDNFilter, const char* name, bool value) = nullptr;
  void (*setFilterInt)(OIDNFilter, const char* name, int value) = nullptr;
  void (*commitFilter)(OIDNFilter) = nullptr;
  void (*executeFilter)(OIDNFilter) = nullptr;
  void (*releaseFilter)(OIDNFilter) = nullptr;
};

/// The outcome of the one load per process.
struct Loaded {
  OidnApi api;
  std::string path;   ///< what was loaded
  std::string error;  ///< empty on success
};

constexpr const char* kSoname = "libOpenImageDenoise.so.2";
constexpr const char* kPyoidnLib = "pyoidn/oidn/lib/libOpenImageDenoise.so.2";
constexpr const char* kInstallHint =
    "install it with `python3 -m pip install pyoidn` (for the python3 on PATH), or set "
    "TESSERA_OIDN_LIBRARY=/path/to/libOpenImageDenoise.so.2";

bool is_file(const std::string& p) {
  struct stat st {};
  return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

/// Something exists under `p` (stat: names are looked up, nothing is opened).
bool exists(const std::string& p) {
  struct stat st {};
  return ::stat(p.c_str(), &st) == 0;
}

/// An absolute, literal location: starts with '/' and holds no loader token ($ORIGIN, $LIB).
bool is_absolute(const std::string& p) { return !p.empty() && p[0] == '/' && p.find('$') == std::string::npos; }

/// The entries of a search-path variable (split at ':', and also at ';' for the loader's).
std::vector<std::string> split_path_list(const char* value, const char* separators) {
  std::vector<std::string> out;
  if (!value) return out;
  const std::string all(value);
  for (std::size_t a = 0; a <= all.size();) {
    std::size_t b = all.find_first_of(separators, a);
    if (b == std::string::npos) b = all.size();
    out.push_back(all.substr(a, b - a));
    a = b + 1;
  }
  return out;
}

void glob_into(const std::string& pattern, std::vector<std::string>& out) {
  glob_t g{};
  if (::glob(pattern.c_str(), 0, nullptr, &g) == 0)
    for (std::size_t i = 0; i < g.gl_pathc; ++i)
      if (is_file(g.gl_pathv[i])) out.emplace_back(g.gl_pathv[i]);
  ::globfree(&g);
}

/// The first `python3` in an absolute PATH entry that is an executable file, "" if none.
/// Empty and relative entries (the working directory) are skipped.
std::string python3_on_path() {
  for (const std::string& dir : split_path_list(std::getenv("PATH"), ":")) {
    if (!is_absolute(dir)) continue;
    const std::string exe = dir + "/python3";
    if (is_file(exe) && ::access(exe.c_str(), X_OK) == 0) return exe;
  }
  return "";
}

/// The pyoidn candidates (step 3 of denoiser.h).
std::vector<std::string> pyoidn_paths() {
  std::vector<std::string> out;
  const std::string py = python3_on_path();
  if (!py.empty()) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(py).parent_path();
    glob_into((dir / "../lib/python3*/site-packages/").string() + kPyoidnLib, out);
    std::error_code ec;
    const fs::path real = fs::canonical(py, ec);
    if (!ec && real.parent_path() != fs::canonical(dir, ec))
      glob_into((real.parent_path() / "../lib/python3*/site-packages/").string() + kPyoidnLib, out);
  }
  if (const char* home = std::getenv("HOME"); home && is_absolute(home))
    glob_into(std::string(home) + "/.local/lib/python3*/site-packages/" + kPyoidnLib, out);
  glob_into(std::string("/usr/local/lib/python3*/dist-packages/") + kPyoidnLib, out);
  return out;
}

/// The candidates of the lookup in order, and the places passed over with why.
struct Lookup {
  std::vector<std::string> paths;
  std::vector<std::string> skipped;
};

/// Steps 2 and 3 of denoiser.h. The soname is resolved over LD_LIBRARY_PATH here, so every
/// file loaded is checked first; the loader's own search (dlopen by soname) is left for the
/// cache and the system directories, and is skipped when LD_LIBRARY_PATH would lead it to a
/// file that was not checked: one under a relative, empty or token entry.
Lookup lookup() {
  Lookup l;
  bool soname_in_env = false;
  for (const std::string& dir : split_path_list(std::getenv("LD_LIBRARY_PATH"), ":;")) {
    const std::string file = (dir.empty() ? std::string(".") : dir) + "/" + kSoname;
    if (dir.find('$') != std::string::npos) {
      soname_in_env = true;  // the loader expands it; it cannot be checked here
      l.skipped.push_back("LD_LIBRARY_PATH entry '" + dir + "': has a loader token, not searched");
    } else if (!exists(file)) {
      continue;
    } else if (is_absolute(dir)) {
      soname_in_env = true;
      l.paths.push_back(file);
    } else {
      soname_in_env = true;
      l.skipped.push_back(file + ": in the relative LD_LIBRARY_PATH entry '" + dir +
                          "', not loaded (only absolute locations are searched)");
    }
  }
  if (!soname_in_env) l.paths.emplace_back(kSoname);
  for (std::string& p : pyoidn_paths()) l.paths.push_back(std::move(p));
  return l;
}

/// Why `path` must not be given to dlopen, "" when it may: a regular file, opened with
/// O_NONBLOCK and typed by fstat (regular_file.h), so a FIFO or a terminal cannot block.
/// A bare soname is the loader's to find.
std::string not_loadable(const std::string& path) {
  if (path.find('/') == std::string::npos) return "";
  try {
    const RegularFile f(path);
    return "";
  } catch (const std::exception& e) {
    return e.what();
  }
}

/// dlopen + dlsym of every function; "" on success, else why not.
std::string try_load(const std::string& path, Loaded& l) {
  if (std::string why = not_loadable(path); !why.empty()) return why;
  ::dlerror();
  void* h = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!h) {
    const char* e = ::dlerror();
    return e ? e : "dlopen failed";
  }
  OidnApi api;
  const auto sym = [&](auto& fn, const char* name) {
    if (fn == nullptr && (fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(::dlsym(h, name))) == nullptr)
      throw std::string(name);
  };
  try {
    sym(api.newDevice, "oidnNewDevice");
    sym(api.commitDevice, "oidnCommitDevice");
    sym(api.getDeviceError, "oidnGetDeviceError");
    sym(api.getDeviceInt, "oidnGetDeviceInt");
    sym(api.setDeviceInt, "oidnSetDeviceInt");
    sym(api.setDeviceBool, "oidnSetDeviceBool");
    sym(api.releaseDevice, "oidnReleaseDevice");
    sym(api.newFilter, "oidnNewFilter");
    sym(api.setSharedFilterImage, "oidnSetSharedFilterImage");
    sym(api.setFilterBool, "oidnSetFilterBool");
    sym(api.setFilterInt, "oidnSetFilterInt");
    sym(api.commitFilter, "oidnCommitFilter");
    sym(api.executeFilter, "oidnExecuteFilter");
    sym(api.releaseFilter, "oidnReleaseFilter");
  } catch (const std::string& missing) {
    ::dlclose(h);
    return "not Open Image Denoise 2.x (it has no function " + missing + ")";
  }
  l.api = api;
  l.path = path;
  return "";
}

Loaded load_oidn() {
  Loaded l;
  const char* env = std::getenv("TESSERA_OIDN_LIBRARY");
  if (env && *env) {
    std::string why =
        is_absolute(env) ? try_load(env, l) : "not an absolute path (allowed: /path/to/" + std::string(kSoname) + ")";
    if (!why.empty())
      l.error = "cannot load Intel Open Image Denoise from TESSERA_OIDN_LIBRARY=" + std::string(env) + ": " + why +
                "; point it at libOpenImageDenoise.so.2 of OIDN 2.x, or unset it and " + kInstallHint;
    return l;
  }
  std::string tried = std::string("TESSERA_OIDN_LIBRARY: ") + (env ? "empty (ignored)" : "unset");
  const Lookup places = lookup();
  for (const std::string& p : places.paths) {
    const std::string why = try_load(p, l);
    if (why.empty()) return l;
    tried += "; " + (why.rfind(p, 0) == 0 ? why : p + ": " + why);  // dlerror names it
  }
  for (const std::string& s : places.skipped) tried += "; " + s;
  const std::string py = python3_on_path();
  l.error = "Intel Open Image Denoise 2.x not found (tried " + tried + "; pyoidn of " +
            (py.empty() ? std::string("python3 on PATH: no python3 in an absolute PATH entry") : py) +
            " and the user/system site directories: not installed); " + kInstallHint;
  return l;
}

const Loaded& oidn() {
  static const Loaded loaded = load_oidn();  // once per process, thread-safe
  return loaded;
}

/// The OIDN error of the device, "" if none (clears it).
std::string device_error(const OidnApi& api, OIDNDevice dev) {
  const char* msg = nullptr;
  if (api.getDeviceError(dev, &msg) == kOidnErrorNone) return "";
  return msg && *msg ? msg : "unknown Open Image Denoise error";
}

/// The one CPU device of the process: made on first use, remade when another thread count is
/// asked for; calls take turns on the mutex.
struct DenoiserDevice {
  std::mutex mutex;
  OIDNDevice device = nullptr;
  int asked = 0;    ///< the thread count it was made for
  int threads = 0;  ///< the threads OIDN says it runs on
};
DenoiserDevice g_device;

}  // namespace

std::vector<std::string> oidn_search_paths() {
  const char* env = std::getenv("TESSERA_OIDN_LIBRARY");
  if (env && *env) return {env};
  return lookup().paths;
}

std::string require_denoiser() {
  const Loaded& l = oidn();
  if (!l.error.empty()) throw DenoiserUnavailable(l.error);
  return l.path;
}

int denoiser_threads() {
  const std::lock_guard<std::mutex> lock(g_device.mutex);
  return g_device.threads;
}

void denoise(Image& img, int threads) {
  require_denoiser();
  const OidnApi& api = oidn().api;
  const std::size_t n = static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height);
  if (img.width <= 0 || img.height <= 0 || img.rgba.size() != n * 4)
    throw std::invalid_argument("denoise: image " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                                " with " + std::to_string(img.rgba.size()) + " RGBA floats");
  const bool albedo = img.albedo.size() == n * 3;
  bool normal = albedo && img.normal.size() == n * 3;  // OIDN takes a normal only with an albedo
  if (normal) {
    normal = false;
    for (const float v : img.normal) normal = normal || v != 0.0f;  // phase shading: none
  }
  img.denoised.assign(n * 3, 0.0f);

  // One CPU device per process, made on first use and kept while the thread count asked for
  // stays the same; calls take turns
  const int want = threads > 0 ? threads : tbb::this_task_arena::max_concurrency();
  const std::lock_guard<std::mutex> lock(g_device.mutex);
  if (g_device.device && g_device.asked != want) {
    api.releaseDevice(g_device.device);
    g_device.device = nullptr;
    g_device.threads = 0;
  }
  if (!g_device.device) {
    OIDNDevice d = api.newDevice(kOidnDeviceTypeCpu);
    if (!d) throw std::runtime_error("Open Image Denoise: cannot create a CPU device");
    // Its own arena of `want` threads, not pinned to cores: in situ the launcher binds each
    // rank to its cores, and OIDN's pinning would put every rank's threads on the same ones
    api.setDeviceInt(d, "numThreads", want);
    api.setDeviceBool(d, "setAffinity", false);
    api.commitDevice(d);
    std::string e = device_error(api, d);
    if (e.empty() && api.getDeviceInt(d, "versionMajor") < 2) {
      api.releaseDevice(d);
      throw DenoiserUnavailable(oidn().path + " is older than Open Image Denoise 2.x");
    }
    if (!e.empty()) {
      api.releaseDevice(d);
      throw std::runtime_error("Open Image Denoise: CPU device: " + e);
    }
    g_device.device = d;
    g_device.asked = want;
    g_device.threads = api.getDeviceInt(d, "numThreads");
  }
  const OIDNDevice device = g_device.device;

  // The "RT" filter on the image's own buffers: RGB read from RGBA (16-byte pixels)
  const OIDNFilter f = api.newFilter(device, "RT");
  if (!f) throw std::runtime_error("Open Image Denoise: cannot create the RT filter: " + device_error(api, device));
  const std::size_t w = static_cast<std::size_t>(img.width), h = static_cast<std::size_t>(img.height);
  api.setSharedFilterImage(f, "color", img.rgba.data(), kOidnFormatFloat3, w, h, 0, 4 * sizeof(float), 0);
  if (albedo) api.setSharedFilterImage(f, "albedo", img.albedo.data(), kOidnFormatFloat3, w, h, 0, 0, 0);
  if (normal) api.setSharedFilterImage(f, "normal", img.normal.data(), kOidnFormatFloat3, w, h, 0, 0, 0);
  api.setSharedFilterImage(f, "output", img.denoised.data(), kOidnFormatFloat3, w, h, 0, 0, 0);
  api.setFilterBool(f, "hdr", true);
  api.setFilterInt(f, "maxMemoryMB", kDenoiserMaxMemoryMB);  // larger images go in tiles
  api.commitFilter(f);
  std::string e = device_error(api, device);
  if (e.empty()) {
    api.executeFilter(f);
    e = device_error(api, device);
  }
  api.releaseFilter(f);
  if (!e.empty()) {
    img.denoised.clear();
    throw std::runtime_error("Open Image Denoise: " + e);
  }
}

}  // namespace tessera
