#include "bridgefit/core/interrupt.hpp"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <thread>

#include "bridgefit/core/error.hpp"

namespace bridgefit {
namespace {

// The accepted exception to "no global mutable state" (see the header).
std::atomic<int> g_interrupt_signal{0};

void WriteStderr(const std::string& text) {
  const char* data = text.data();
  std::size_t left = text.size();
  while (left > 0) {
    const ssize_t n = ::write(STDERR_FILENO, data, left);
    if (n <= 0) return;
    data += n;
    left -= static_cast<std::size_t>(n);
  }
}

void Watch(InterruptWatchOptions options, sigset_t signals) {
  int signal_number = 0;
  while (sigwait(&signals, &signal_number) != 0) {
  }
  RequestInterrupt(signal_number);
  const auto start = std::chrono::steady_clock::now();
  // A second signal during the grace period ends the wait at once.
  const timespec step{0, 20'000'000};
  while (std::chrono::steady_clock::now() - start < options.grace) {
    siginfo_t info;
    if (sigtimedwait(&signals, &info, &step) > 0) break;
  }
  // The command did not stop by itself within the grace period.
  RemoveOwnTemporaries(options.outputs);
  WriteStderr(options.what + ": interrupted by " + SignalName(signal_number) +
              "; stopped, no output written.\n");
  ::_exit(128 + signal_number);
}

}  // namespace

int InterruptSignal() { return g_interrupt_signal.load(std::memory_order_relaxed); }

void RequestInterrupt(int signal_number) {
  int expected = 0;
  g_interrupt_signal.compare_exchange_strong(expected, signal_number);
}

std::string SignalName(int signal_number) {
  if (signal_number == SIGINT) return "SIGINT";
  if (signal_number == SIGTERM) return "SIGTERM";
  return "signal " + std::to_string(signal_number);
}

void ThrowIfInterrupted(const std::string& stage) {
  const int signal_number = InterruptSignal();
  if (signal_number == 0) return;
  throw Error(ErrorKind::kInterrupted,
              "interrupted by " + SignalName(signal_number) + " during " + stage);
}

void StartInterruptWatcher(InterruptWatchOptions options) {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  std::thread(Watch, std::move(options), signals).detach();
}

void RemoveOwnTemporaries(const std::vector<std::filesystem::path>& paths) {
  const std::string marker = ".tmp-" + std::to_string(::getpid()) + "-";
  auto sweep = [&marker](const std::filesystem::path& folder) {
    std::error_code ec;
    for (auto it = std::filesystem::directory_iterator(folder, ec);
         !ec && it != std::filesystem::directory_iterator(); it.increment(ec)) {
      const std::string name = it->path().filename().string();
      if (name.size() > 1 && name[0] == '.' && name.find(marker) != std::string::npos) {
        std::error_code ignored;
        std::filesystem::remove_all(it->path(), ignored);
      }
    }
  };
  for (const std::filesystem::path& path : paths) {
    const std::filesystem::path parent =
        path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
    std::error_code ec;
    if (std::filesystem::is_directory(parent, ec)) sweep(parent);
    if (std::filesystem::is_directory(path, ec)) sweep(path);
  }
}

}  // namespace bridgefit
