// What `vox` does when it is interrupted: SIGINT, SIGTERM and SIGHUP delete
// the temporary files of the outputs being written (existing outputs are never
// touched: they are only replaced by the final rename), then the directories
// the run created for them that are left empty (vox::CreatedDirectories), print one line on
// stderr and exit with 130, 143 or 129 (128 + the signal, as shells report
// it). A signal that arrives while the outputs are being renamed into place
// waits for the renames (microseconds), so an interrupt never leaves some new
// outputs beside old ones; a signal after that (while the run frees memory or
// prints its summary) leaves those complete outputs and says so. A second
// signal while the first is handled changes nothing. A
// signal the parent ignores (SIGINT in a background job of a script, SIGHUP
// under nohup) stays ignored. SIGXFSZ (a `ulimit -f` exceeded) is ignored so the write fails with
// "File too large" and the run ends like any other failed write: exit 4, the
// output named, nothing left behind. README "Conventions of every command".
#pragma once

namespace voxcli {

/// Installs the handlers for `command` (named in the message). Idempotent;
/// the last call wins (each command module installs its own).
void installSignalCleanup(const char* command);

}  // namespace voxcli
