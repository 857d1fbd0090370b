#include "tools/cli/signal_cleanup.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
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

void writeCount(int value) {
  char digits[16];
  int n = sizeof digits;
  digits[--n] = '\0';
  if (value == 0) digits[--n] = '0';
  for (int v = value; v > 0 && n > 0; v /= 10) digits[--n] = char('0' + v % 10);
  writeAll(digits + n);
}

std::atomic<bool> gHandling{false};

// Async-signal-safe only: unlink, rmdir, write, pause, _exit.
extern "C" void onTerminatingSignal(int sig) {
  // While outputs are renamed into place the signal waits (microseconds): the
  // commit raises it again when every rename is done.
  if (vox::deferSignalDuringCommit(sig)) return;
  // Signals reach any thread: the first handler speaks and exits, a second
  // one (another thread, another signal) waits for that exit.
  if (gHandling.exchange(true)) {
    for (;;) ::pause();
  }
  const int removed = vox::removeUncommittedOutputs();
  vox::removeCreatedDirectories();  // once emptied of the temporaries: build-atlas's -o DIR
  const int committed = vox::committedOutputCount();
  const char* name = sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "SIGHUP";
  writeAll("\n");
  writeAll(gCommand);
  writeAll(": interrupted by ");
  writeAll(name);
  if (removed > 0 && committed > 0) {
    // Only after a failed commit that could not put everything back (its error says which).
    writeAll("; ");
    writeCount(removed);
    writeAll(removed == 1 ? " unfinished output removed, " : " unfinished outputs removed, ");
    writeCount(committed);
    writeAll(committed == 1 ? " output already in place\n" : " outputs already in place\n");
  } else if (removed > 0) {
    writeAll("; ");
    writeCount(removed);
    writeAll(removed == 1 ? " unfinished output removed" : " unfinished outputs removed");
    writeAll(", existing files left as they were\n");
  } else if (committed > 0) {
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
  sa.sa_flags = SA_RESTART;  // a deferred signal returns: the calls it interrupted carry on
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
