#pragma once
// The command line of tessera-render (docs/cli.md) read into the render job's Args.
#include <tessera/job/args.h>

namespace tessera::cli {

using job::Args;

/// Parses argv; throws std::runtime_error with a one-line message for a bad command line.
/// Options take their value as the next argument or after '=' (--spp=64).
Args parse_args(int argc, const char* const* argv);

/// The synopsis and option list, for --help.
const char* usage();

}  // namespace tessera::cli
