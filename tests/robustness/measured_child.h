#pragma once
/// Shared by the robustness tests that measure memory: run a program in a scratch directory as
/// a child (fork + execve, a watchdog alarm) and take its peak RSS from wait4. Test code only.
#include "cli_run.h"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>
#include <vector>

extern char** environ;

namespace tessera_test {

struct MeasuredRun {
  int status = -1;        ///< exit status; 128 + N for signal N (SIGALRM: the watchdog)
  long peak_rss_kib = 0;  ///< ru_maxrss of the child (KiB)
  std::string out, err;
};

/// Runs `argv[0]` with `argv` inside `dir`, the environment of this process plus `env`
/// ("NAME=value", replacing a variable of the same name), stdout and stderr to files; killed
/// by SIGALRM after `timeout_s`.
inline MeasuredRun run_measured(const TempDir& dir, const std::vector<std::string>& argv,
                                const std::vector<std::string>& env = {}, unsigned timeout_s = 60) {
  // Everything the child needs is built before fork (only async-signal-safe calls after it)
  std::vector<std::string> env_strings;
  for (char** e = environ; *e; ++e) {
    const std::string var(*e);
    bool replaced = false;
    for (const std::string& x : env) replaced = replaced || var.compare(0, x.find('=') + 1, x, 0, x.find('=') + 1) == 0;
    if (!replaced) env_strings.push_back(var);
  }
  env_strings.insert(env_strings.end(), env.begin(), env.end());
  std::vector<char*> envp, args;
  for (std::string& s : env_strings) envp.push_back(s.data());
  envp.push_back(nullptr);
  std::vector<std::string> argv_copy = argv;
  for (std::string& s : argv_copy) args.push_back(s.data());
  args.push_back(nullptr);
  const std::string cwd = dir.path().string(), out = dir.file("child.out"), err = dir.file("child.err");

  const pid_t pid = ::fork();
  if (pid == 0) {
    const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (o < 0 || e < 0 || ::dup2(o, 1) < 0 || ::dup2(e, 2) < 0 || ::chdir(cwd.c_str()) != 0) ::_exit(126);
    ::alarm(timeout_s);  // survives execve: a child that hangs dies of SIGALRM
    ::execve(args[0], args.data(), envp.data());
    ::_exit(127);
  }
  MeasuredRun r;
  if (pid < 0) return r;
  int st = 0;
  struct rusage ru {};
  if (::wait4(pid, &st, 0, &ru) != pid) return r;
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : WIFSIGNALED(st) ? 128 + WTERMSIG(st) : -1;
  r.peak_rss_kib = ru.ru_maxrss;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

}  // namespace tessera_test
