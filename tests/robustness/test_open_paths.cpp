// Robustness: nothing Tessera opens can block it, and the denoiser's library search follows
// only absolute locations (denoiser.h, docs/cli.md "Denoising"). A FIFO, a terminal, a device
// or a directory named by TESSERA_OIDN_LIBRARY or found under the soname in LD_LIBRARY_PATH
// is refused at once, naming its kind, instead of blocking dlopen; a library planted under a
// relative or empty PATH or LD_LIBRARY_PATH entry, or a relative HOME, is never loaded. The
// denoiser is loaded once per process, so the lookup runs in tessera-render children (with a
// timeout: a regression fails instead of hanging CTest) or through oidn_search_paths(), which
// loads nothing. An existing Cinema data.csv that is a FIFO is refused without blocking, and
// the temporary files of atomic writes are made new (atomic_output.h): a FIFO or a link planted
// under the name is passed over, never opened.
#include "cli_run.h"
#include "denoise_scene.h"
#include "outputs/cinema.h"
#include "scoped_env.h"

#include <tessera/denoiser.h>

#include <catch2/catch.hpp>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <future>
#include <optional>
#include <string>
#include <thread>

using Catch::Matchers::Contains;
using tessera_test::TempDir;
using namespace tessera_test::denoise;
namespace fs = std::filesystem;

namespace {

void make_fifo(const std::string& path) { REQUIRE(::mkfifo(path.c_str(), 0600) == 0); }

/// A file that looks like the pyoidn library but is not one (dlopen would fail naming it).
void plant(const fs::path& path) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << "planted, not a library";
}

/// An executable `python3` script at `path`.
void fake_python(const fs::path& path) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << "#!/bin/sh\n";
  fs::permissions(path, fs::perms::owner_all);
}

/// The environment for a lookup that finds no real OIDN in the user's places: no
/// TESSERA_OIDN_LIBRARY, a fresh HOME, PATH without the project's venv.
std::string clean_env(const TempDir& dir) {
  fs::create_directories(dir.path() / "home");
  return "env -u TESSERA_OIDN_LIBRARY -u LD_LIBRARY_PATH HOME=" + dir.file("home") + " PATH=/usr/bin:/bin";
}

using tessera_test::ScopedEnv;

/// Runs `fn` on a thread; if it has not returned within `seconds`, opens the write end of
/// `fifo` (which releases a reader blocked opening it) and returns false.
template <class Fn>
bool returns_without_blocking(const std::string& fifo, Fn fn, double seconds = 10.0) {
  std::future<void> done = std::async(std::launch::async, fn);
  if (done.wait_for(std::chrono::duration<double>(seconds)) == std::future_status::ready) {
    done.get();
    return true;
  }
  while (done.wait_for(std::chrono::milliseconds(10)) != std::future_status::ready) {
    const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
    if (fd >= 0) ::close(fd);
  }
  try {
    done.get();
  } catch (...) {
  }
  return false;
}

}  // namespace

#ifdef TESSERA_RENDER_EXE
TEST_CASE("open paths: TESSERA_OIDN_LIBRARY naming a FIFO, a device, a terminal or a directory is refused at once",
          "[robustness][open_paths]") {
  TempDir dir;
  write_cli_scene(dir, true);
  make_fifo(dir.file("pipe.so"));
  fs::create_directories(dir.path() / "libdir");
  const struct {
    std::string path, kind;
  } cases[] = {{dir.file("pipe.so"), " is a FIFO (allowed: a regular file)"},
               {"/dev/null", " is a character device (allowed: a regular file)"},
               {dir.file("libdir"), " is a directory (allowed: a regular file)"},
               {"/dev/tty", ""}};  // without a controlling terminal it cannot be opened at all
  for (const auto& c : cases) {
    INFO(c.path);
    const tessera_test::CliRun r =
        tessera_test::run_cli(dir, "scene.yaml --quiet", "TESSERA_OIDN_LIBRARY=" + c.path, 20);
    CHECK(r.status == 1);  // 124: dlopen blocked until the timeout
    CHECK_THAT(r.err, Contains("cannot load Intel Open Image Denoise from TESSERA_OIDN_LIBRARY=" + c.path + ": " +
                               c.path + c.kind));
    CHECK_FALSE(fs::exists(dir.path() / "results"));
  }
}

TEST_CASE("open paths: a relative TESSERA_OIDN_LIBRARY is an error naming it", "[robustness][open_paths]") {
  TempDir dir;
  write_cli_scene(dir, true);
  plant(dir.path() / "libOpenImageDenoise.so.2");
  const tessera_test::CliRun r =
      tessera_test::run_cli(dir, "scene.yaml --quiet", "TESSERA_OIDN_LIBRARY=libOpenImageDenoise.so.2", 20);
  CHECK(r.status == 1);
  CHECK_THAT(r.err, Contains("TESSERA_OIDN_LIBRARY=libOpenImageDenoise.so.2: not an absolute path (allowed: "
                             "/path/to/libOpenImageDenoise.so.2)"));
}

TEST_CASE("open paths: a library planted under a relative PATH entry or a relative HOME is not loaded",
          "[robustness][open_paths]") {
  TempDir dir;
  write_cli_scene(dir, true);
  // bin/python3 with its venv's pyoidn beside it, and a user site under home/, all relative
  // to the working directory
  fake_python(dir.path() / "bin/python3");
  plant(dir.path() / "lib/python3.11/site-packages/pyoidn/oidn/lib/libOpenImageDenoise.so.2");
  plant(dir.path() / "home/.local/lib/python3.11/site-packages/pyoidn/oidn/lib/libOpenImageDenoise.so.2");
  const tessera_test::CliRun r =
      tessera_test::run_cli(dir, "scene.yaml --quiet",
                            "env -u TESSERA_OIDN_LIBRARY -u LD_LIBRARY_PATH HOME=home PATH=:bin:/usr/bin:/bin", 20);
  INFO(r.err);
  CHECK(r.status != 124);
  CHECK(r.err.find("site-packages/pyoidn") == std::string::npos);  // never tried, so never named
  if (r.status == 1) CHECK_THAT(r.err, Contains("Intel Open Image Denoise 2.x not found"));
}

TEST_CASE("open paths: the soname under LD_LIBRARY_PATH is checked first: a FIFO is refused, a relative entry skipped",
          "[robustness][open_paths]") {
  TempDir dir;
  write_cli_scene(dir, true);
  fs::create_directories(dir.path() / "fifo_dir");
  const std::string fifo = dir.file("fifo_dir/libOpenImageDenoise.so.2");
  make_fifo(fifo);
  const std::string env = clean_env(dir);
  const tessera_test::CliRun r =
      tessera_test::run_cli(dir, "scene.yaml --quiet", env + " LD_LIBRARY_PATH=" + dir.file("fifo_dir"), 20);
  INFO(r.err);
  CHECK(r.status != 124);  // the loader would block opening the FIFO
  if (r.status != 0) CHECK_THAT(r.err, Contains(fifo + " is a FIFO (allowed: a regular file)"));

  // A relative entry (and an empty one, the working directory) holding the soname
  plant(dir.path() / "rel/libOpenImageDenoise.so.2");
  const tessera_test::CliRun rel = tessera_test::run_cli(dir, "scene.yaml --quiet", env + " LD_LIBRARY_PATH=rel", 20);
  INFO(rel.err);
  CHECK(rel.status != 124);
  if (rel.status != 0)
    CHECK_THAT(rel.err, Contains("rel/libOpenImageDenoise.so.2: in the relative LD_LIBRARY_PATH entry 'rel', not "
                                 "loaded (only absolute locations are searched)"));
  CHECK(rel.err.find("invalid ELF header") == std::string::npos);
  CHECK(rel.err.find("file too short") == std::string::npos);
}
#endif

TEST_CASE("open paths: the lookup lists no candidate under a relative or empty PATH entry or a relative HOME",
          "[robustness][open_paths]") {
  TempDir dir;
  fake_python(dir.path() / "python3");
  fake_python(dir.path() / "bin/python3");
  plant(dir.path() / "lib/python3.11/site-packages/pyoidn/oidn/lib/libOpenImageDenoise.so.2");
  plant(dir.path() / "home/.local/lib/python3.11/site-packages/pyoidn/oidn/lib/libOpenImageDenoise.so.2");
  const fs::path cwd = fs::current_path();
  fs::current_path(dir.path());
  std::vector<std::string> paths;
  {
    const ScopedEnv lib("TESSERA_OIDN_LIBRARY", std::nullopt);
    const ScopedEnv ld("LD_LIBRARY_PATH", std::string(":rel"));
    const ScopedEnv path("PATH", std::string(":bin:."));
    const ScopedEnv home("HOME", std::string("home"));
    paths = tessera::oidn_search_paths();
  }
  fs::current_path(cwd);
  for (const std::string& p : paths) {
    INFO(p);
    CHECK((p == "libOpenImageDenoise.so.2" || p.front() == '/'));
    CHECK(p.find(dir.path().string()) == std::string::npos);
  }
}

TEST_CASE("open paths: a Cinema data.csv that is a FIFO is refused without blocking", "[robustness][open_paths]") {
  TempDir dir;
  const std::string fifo = dir.file("data.csv");
  make_fifo(fifo);
  tessera::insitu::CinemaDatabase db(dir.path().string());
  std::string error;
  const bool returned = returns_without_blocking(fifo, [&] {
    try {
      db.set_row(0.0, 0.0, 0.0, "a.png");
    } catch (const std::exception& e) {
      error = e.what();
    }
  });
  CHECK(returned);
  CHECK_THAT(error, Contains(fifo + " is a FIFO (allowed: a regular file)"));
}

#ifdef TESSERA_RENDER_EXE
TEST_CASE("open paths: FIFOs and a link planted under the outputs' temporary names are passed over",
          "[robustness][open_paths]") {
  TempDir dir;
  write_cli_scene(dir, false);
  fs::create_directories(dir.path() / "results");
  dir.write("victim.txt", "untouched");
  // The renderer starts after a second, under the pid of the shell that execs it: time to
  // plant the names its writes would use (path.tmp.<pid>.<n>, n counting from 0)
  const std::string cmd = "sleep 1; exec '" TESSERA_RENDER_EXE "' scene.yaml --quiet > cli.out 2> cli.err";
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (::chdir(dir.path().c_str()) != 0) ::_exit(126);
    ::alarm(30);  // survives exec: a render blocked on a FIFO dies of SIGALRM
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  REQUIRE(pid > 0);
  std::vector<std::string> planted;
  for (const char* name : {"d.exr", "d.png"})
    for (int n = 0; n < 8; ++n) {
      planted.push_back((dir.path() / "results" / name).string() + ".tmp." + std::to_string(pid) + "." +
                        std::to_string(n));
      make_fifo(planted.back());
    }
  fs::create_symlink(dir.file("victim.txt"), (dir.path() / "results/d.png.tmp.").string() + std::to_string(pid) + ".8");
  int st = 0;
  REQUIRE(::waitpid(pid, &st, 0) == pid);
  INFO(tessera_test::slurp(dir.path() / "cli.err"));
  CHECK(WIFEXITED(st));  // not killed by the watchdog
  CHECK((WIFEXITED(st) && WEXITSTATUS(st) == 0));
  CHECK(fs::is_regular_file(dir.path() / "results/d.exr"));
  CHECK(fs::is_regular_file(dir.path() / "results/d.png"));
  CHECK(tessera_test::slurp(dir.path() / "victim.txt") == "untouched");
  for (const std::string& p : planted) CHECK(fs::is_fifo(p));  // left as they were
}
#endif
