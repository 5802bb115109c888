#include <tessera/number_text.h>

#include <charconv>
#include <cstdio>
#include <system_error>

namespace tessera {

std::string format_number(double v) {
  char buf[64];  // the longest shortest form of a double is 24 characters
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, ec == std::errc() ? end : buf);
}

std::string short_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace tessera
