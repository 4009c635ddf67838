// SIGINT / SIGTERM: the flag and AtomicOutput in a child process (the flag
// is process-wide), and the CLI: a running fit is stopped within a second,
// says what was interrupted, exits 130 / 143 and leaves no output file.
#include "bridgefit/core/interrupt.hpp"

#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "bridgefit/core/atomic_file.hpp"
#include "bridgefit/core/error.hpp"

namespace bridgefit {
namespace {

namespace fs = std::filesystem;

// Runs `body` in a forked child; the child's exit code (-1 on a signal).
template <class F>
int InChild(F&& body) {
  const pid_t pid = fork();
  if (pid == 0) _exit(body());
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(Interrupt, FlagThrowsAndAtomicOutputCommitsNothing) {
  const fs::path dir = fs::temp_directory_path() / ("bf_interrupt_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const int code = InChild([&] {
    if (InterruptRequested()) return 10;
    ThrowIfInterrupted("nothing");  // no throw before a signal
    RequestInterrupt(SIGTERM);
    if (InterruptSignal() != SIGTERM) return 11;
    try {
      ThrowIfInterrupted("the fit");
      return 12;
    } catch (const Error& e) {
      if (e.kind() != ErrorKind::kInterrupted) return 13;
      if (std::string(e.what()).find("SIGTERM during the fit") == std::string::npos) return 14;
    }
    try {
      AtomicOutput output(dir / "out.txt");
      std::ofstream(output.temporary_path()) << "half";
      output.Commit();
      return 15;
    } catch (const Error& e) {
      if (e.kind() != ErrorKind::kInterrupted) return 16;
    }
    return fs::exists(dir / "out.txt") ? 17 : 0;
  });
  EXPECT_EQ(code, 0);
  EXPECT_TRUE(fs::is_empty(dir)) << "a temporary or output file was left behind";
  fs::remove_all(dir);
}

struct Stopped {
  int exit_code = -1;     // -1 when ended by a signal
  double stop_s = 1e9;    // from the signal to the exit
  std::string err;
};

// True once `pid` blocks SIGINT and SIGTERM: its interrupt watcher is up
// (core/interrupt.hpp blocks both in every thread). Linux: /proc/PID/status.
bool WatcherInstalled(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("SigBlk:", 0) != 0) continue;
    const unsigned long long mask = std::stoull(line.substr(7), nullptr, 16);
    const unsigned long long want = (1ull << (SIGINT - 1)) | (1ull << (SIGTERM - 1));
    return (mask & want) == want;
  }
  return false;
}

// Starts `bridgefit args...`, waits until its interrupt watcher is installed
// (a fixed delay from the fork raced the start-up on a loaded machine), then
// `delay` more, sends `signal_number` and waits.
Stopped RunAndSignal(const std::vector<std::string>& args, int signal_number,
                     std::chrono::milliseconds delay, const fs::path& err_path) {
  std::vector<char*> argv;
  std::string cli = BRIDGEFIT_CLI;
  argv.push_back(cli.data());
  std::vector<std::string> copy = args;
  for (std::string& a : copy) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    const int err = open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int null = open("/dev/null", O_WRONLY);
    dup2(err, STDERR_FILENO);
    dup2(null, STDOUT_FILENO);
    execv(argv[0], argv.data());
    _exit(127);
  }
  const auto started = std::chrono::steady_clock::now();
  while (!WatcherInstalled(pid) && std::chrono::steady_clock::now() - started < std::chrono::seconds(30)) {
    int ignored = 0;
    if (waitpid(pid, &ignored, WNOHANG) == pid) {
      ADD_FAILURE() << "the command ended before its interrupt watcher was seen";
      return {};
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::this_thread::sleep_for(delay);
  Stopped result;
  int status = 0;
  if (waitpid(pid, &status, WNOHANG) == pid) {
    ADD_FAILURE() << "the command ended before the signal: make it longer";
  } else {
    const auto sent = std::chrono::steady_clock::now();
    kill(pid, signal_number);
    waitpid(pid, &status, 0);
    result.stop_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  }
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(err_path);
  std::stringstream text;
  text << in.rdbuf();
  result.err = text.str();
  return result;
}

// A fit with profiles on the MDF sample record: several seconds of work.
std::vector<std::string> LongFit(const fs::path& out) {
  const std::string sample = std::string(BRIDGEFIT_SOURCE_DIR) + "/data_samples/mdf_ct/";
  return {"fit", sample + "record.csv", "--scene", sample + "scene.toml", "--law", "cubic",
          "--starts", "32", "--out", out.string()};
}

void ExpectStoppedCleanly(int signal_number, int expected_exit, const char* name) {
  const fs::path dir = fs::temp_directory_path() / ("bf_sigint_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  // stderr goes beside the folder (which must stay empty), one file per test
  // process: the SIGINT and SIGTERM tests run side by side under ctest -j.
  const fs::path err_path =
      fs::temp_directory_path() / ("bf_sigint_err_" + std::to_string(getpid()) + ".txt");
  const Stopped s = RunAndSignal(LongFit(dir / "fit.h5"), signal_number,
                                 std::chrono::milliseconds(300), err_path);
  EXPECT_EQ(s.exit_code, expected_exit) << s.err;
  EXPECT_LT(s.stop_s, 1.0) << "stopped " << s.stop_s << " s after the signal";
  EXPECT_NE(s.err.find(std::string("interrupted by ") + name), std::string::npos) << s.err;
  EXPECT_NE(s.err.find("bridgefit fit"), std::string::npos) << s.err;  // what was interrupted
  EXPECT_NE(s.err.find("no output written"), std::string::npos) << s.err;
  EXPECT_FALSE(fs::exists(dir / "fit.h5"));
  EXPECT_TRUE(fs::is_empty(dir)) << "a partial or temporary file was left behind";
  fs::remove_all(dir);
  fs::remove(err_path);
}

TEST(Interrupt, SigintStopsARunningFitWithinASecond) { ExpectStoppedCleanly(SIGINT, 130, "SIGINT"); }

TEST(Interrupt, SigtermStopsARunningFitWithinASecond) {
  ExpectStoppedCleanly(SIGTERM, 143, "SIGTERM");
}

}  // namespace
}  // namespace bridgefit
