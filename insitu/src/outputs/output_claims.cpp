// The output directories claimed by the adapters open in this process (output_claims.h).
#include "outputs/output_claims.h"

#include <tessera/message_text.h>

#include <filesystem>
#include <map>
#include <mutex>
#include <stdexcept>
#include <system_error>
#include <utility>

namespace tessera::insitu {
namespace {

// Never destroyed (still reachable, not a leak): an adapter that is a static object, or one a
// language runtime releases late, may release its claim after the statics of this file would
// have been destroyed at exit.
std::mutex& claims_mutex() {
  static std::mutex* const m = new std::mutex;
  return *m;
}

/// normalised directory -> the config path of the adapter holding it
std::map<std::string, std::string>& claims() {
  static auto* const c = new std::map<std::string, std::string>;
  return *c;
}

std::string normalised(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path p = fs::absolute(dir.empty() ? fs::path(".") : fs::path(dir), ec);
  if (ec) p = fs::path(dir);
  fs::path canonical = fs::weakly_canonical(p, ec);
  if (ec) canonical = p.lexically_normal();
  std::string s = canonical.lexically_normal().string();
  while (s.size() > 1 && s.back() == '/') s.pop_back();
  return s;
}

}  // namespace

OutputClaim::OutputClaim(const std::string& output_dir, const std::string& config_path) {
  const std::string key = normalised(output_dir);
  const std::lock_guard<std::mutex> lock(claims_mutex());
  const auto [it, inserted] = claims().emplace(key, config_path);
  if (!inserted)
    throw std::invalid_argument(
        "tessera.output_dir " + shown_path(output_dir) + " (" + shown_path(key) +
        ") is the output directory of another adapter open in this process (opened from " + shown_path(it->second) +
        "): both would write tessera_effective_config.yaml and their images there; give each adapter its own "
        "output_dir (tessera_open_with_output_dir, or the config's tessera.output_dir)");
  m_key = key;
}

OutputClaim::~OutputClaim() { release(); }

OutputClaim::OutputClaim(OutputClaim&& other) noexcept : m_key(std::exchange(other.m_key, std::string())) {}

OutputClaim& OutputClaim::operator=(OutputClaim&& other) noexcept {
  if (this != &other) {
    release();
    m_key = std::exchange(other.m_key, std::string());
  }
  return *this;
}

void OutputClaim::release() noexcept {
  if (m_key.empty()) return;
  try {
    const std::lock_guard<std::mutex> lock(claims_mutex());
    claims().erase(m_key);
  } catch (...) {
    // (a mutex that cannot be locked: the claim stays; nothing else to do in a destructor)
  }
  m_key.clear();
}

}  // namespace tessera::insitu
