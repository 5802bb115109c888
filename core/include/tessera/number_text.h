#pragma once
/// Numbers as text, the two ways Tessera writes them, each defined once.
/// Thread-safe (pure functions), locale-independent for format_number.
#include <string>

namespace tessera {

/// Shortest text that reads back as exactly `v` (std::to_chars): "0.1", "1e+300", "nan",
/// "inf", "-inf". Two doubles that differ never print alike. For values written to files
/// that are read back (YAML, JSON, Cinema's data.csv) and for messages that must tell
/// nearby values apart.
std::string format_number(double v);

/// `v` with six significant digits (printf's "%.6g"): "0.5", "1e+308", "nan". For messages,
/// where a value must stay short (never std::to_string's 300 digits or "0.000000").
std::string short_number(double v);

}  // namespace tessera
