// vox::Error — the single exception type libvox and formats/ throw.
//
// The library never prints and never exits: it throws an Error whose message names
// the file, the element and what to do, and whose kind tells the CLI which
// documented exit code to use (tools/cli/cli.h maps kinds to codes).
#pragma once

#include <stdexcept>
#include <string>

namespace vox {

enum class ErrorKind {
  Usage,     // the options make no sense together (exit 2)
  BadInput,  // an input file is missing, malformed or not what was expected (exit 3)
  Io,        // the system failed: cannot write an output, disk full (exit 4)
  Internal,  // a bug: an invariant did not hold (exit 4)
};

struct Error : std::runtime_error {
  ErrorKind kind;
  Error(ErrorKind k, const std::string& message) : std::runtime_error(message), kind(k) {}
};

[[noreturn]] inline void throwBadInput(const std::string& message) {
  throw Error(ErrorKind::BadInput, message);
}
[[noreturn]] inline void throwUsage(const std::string& message) {
  throw Error(ErrorKind::Usage, message);
}
[[noreturn]] inline void throwIo(const std::string& message) { throw Error(ErrorKind::Io, message); }

}  // namespace vox
