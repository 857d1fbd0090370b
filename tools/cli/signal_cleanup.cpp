#include "tools/cli/signal_cleanup.h"

#include <signal.h>
#include <unistd.h>

#include <cstring>

#include "formats/core/file_util.h"

namespace voxcli {

namespace {

char gCommand[64] = "vox";

void writeAll(const char* s) {
  size_t left = std::strlen(s);
  while (left > 0) {
    const ssize_t n = ::write(STDERR_FILENO, s, left);
    if (n <= 0) return;
    s += n;
    left -= size_t(n);
  }
}

// Async-signal-safe only: unlink, write, _exit.
extern "C" void onTerminatingSignal(int sig) {
  const int removed = vox::removeUncommittedOutputs();
  const char* name = sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "SIGHUP";
  writeAll("\n");
  writeAll(gCommand);
  writeAll(": interrupted by ");
  writeAll(name);
  if (removed > 0) {
    char digits[16];
    int n = sizeof digits;
    digits[--n] = '\0';
    for (int v = removed; v > 0 && n > 0; v /= 10) digits[--n] = char('0' + v % 10);
    writeAll("; ");
    writeAll(digits + n);
    writeAll(removed == 1 ? " unfinished output removed" : " unfinished outputs removed");
    writeAll(", existing files left as they were\n");
  } else if (vox::committedOutputCount() > 0) {
    writeAll("; every output was already in place\n");
  } else {
    writeAll("; nothing was written\n");
  }
  ::_exit(128 + sig);
}

}  // namespace

void installSignalCleanup(const char* command) {
  std::strncpy(gCommand, command, sizeof gCommand - 1);
  struct sigaction sa {};
  sa.sa_handler = onTerminatingSignal;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&sa.sa_mask, sig);  // one handler at a time
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    // A signal the parent chose to ignore (nohup, a background job) stays ignored.
    if (sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    sigaction(sig, &sa, nullptr);
  }
  signal(SIGXFSZ, SIG_IGN);
}

}  // namespace voxcli
