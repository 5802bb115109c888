#pragma once
/// Output file name patterns: `output: {file: "{name}_{step:06d}"}`.
///
/// Placeholders: {name} (the render's name), {step} and {rank} (integers), {time} (double).
/// An optional fmt-like spec follows a colon: `[0][width][.precision][type]`
///   integers: `{step:06d}` (zero pad to 6), `{rank:3}` (space pad), type d or none;
///   time:     `{time:.3f}`, `{time:10.4e}`, types f e g or none (none = shortest exact);
///   name:     `{name:12}` (left-aligned, space pad), type s or none.
/// `{{` and `}}` write literal braces. Anything else is an error naming the placeholder.
#include <cstdint>
#include <string>

namespace tessera::config {

/// Throws std::invalid_argument naming the fault (unknown placeholder, bad spec, unmatched
/// brace, a control character such as NUL, a pattern ending in '/') in a pattern. A valid
/// pattern expands to a non-empty file name with no control characters, so the extensions
/// appended per format always give distinct paths.
///
/// Output stays inside output_dir: a pattern that is an absolute path, has a `.` or `..`
/// component, or whose file name is hidden (starts with '.', e.g. "." or ".{step}") is refused,
/// as written and as expanded.
void validate_output_pattern(const std::string& pattern);

/// The pattern with its placeholders replaced; throws std::invalid_argument like
/// validate_output_pattern, and also when the expanded name (with these values) would leave
/// output_dir or be hidden.
std::string format_output_path(const std::string& pattern, const std::string& name, std::int64_t step, double time,
                               int rank);

}  // namespace tessera::config
