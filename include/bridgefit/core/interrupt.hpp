#pragma once
// SIGINT / SIGTERM for long commands (fit with profiles, DIC, MPM).
//
// The CLI blocks both signals in every thread and starts a watcher thread that
// takes them with sigwait. On a signal the watcher sets the interrupt flag
// (below), gives the command `grace` to stop by itself (a stage that polls
// InterruptRequested() throws Error(kInterrupted), unwinding removes its
// temporary output), then removes what is left of this process's temporary
// outputs (AtomicOutput names them ".NAME.tmp-PID-N"), prints what was
// interrupted and ends the process with 128 + signal (130 / 143).
// AtomicOutput::Commit refuses once the flag is set, so an interrupted run
// never leaves an output file behind.
//
// The flag is the one piece of process-wide mutable state in bridgefit: a
// single std::atomic<int>, set once by the watcher (or by the tests), read by
// any thread. It is the accepted exception to "no global mutable state".

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

namespace bridgefit {

// 0 while no interrupt was requested, else the signal number.
int InterruptSignal();
inline bool InterruptRequested() { return InterruptSignal() != 0; }
// Throws Error(ErrorKind::kInterrupted) naming `stage` when interrupted.
void ThrowIfInterrupted(const std::string& stage);
// Sets the flag as a signal would (tests; the watcher).
void RequestInterrupt(int signal_number);
// "SIGINT", "SIGTERM", else "signal N".
std::string SignalName(int signal_number);

struct InterruptWatchOptions {
  std::string what;  // what is running, e.g. "bridgefit fit record.csv --out fit.h5"
  // Paths named on the command line: temporaries of this process next to them
  // (and inside them, for folders) are removed before a forced exit.
  std::vector<std::filesystem::path> outputs;
  std::chrono::milliseconds grace{400};
};

// Blocks SIGINT and SIGTERM in the calling thread (and so in every thread it
// starts afterwards) and starts the detached watcher. Call once, first thing
// in main, before any thread exists.
void StartInterruptWatcher(InterruptWatchOptions options);

// Removes this process's AtomicOutput temporaries next to and inside `paths`.
void RemoveOwnTemporaries(const std::vector<std::filesystem::path>& paths);

}  // namespace bridgefit
