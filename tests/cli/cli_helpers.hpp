#pragma once
// Runs the `bridgefit` executable and captures exit code, stdout and stderr.

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace bridgefit::testing {

struct CliResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

// `args` is appended to the executable path as shell text.
inline CliResult RunCli(const std::string& args) {
  const auto err_path = std::filesystem::temp_directory_path() /
                        ("bf_cli_stderr_" + std::to_string(::getpid()) + ".txt");
  const std::string command =
      std::string("'") + BRIDGEFIT_CLI + "' " + args + " 2>'" + err_path.string() + "'";
  CliResult result;
  FILE* pipe = ::popen(command.c_str(), "r");
  char buffer[4096];
  size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) result.out.append(buffer, n);
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream err(err_path);
  std::stringstream text;
  text << err.rdbuf();
  result.err = text.str();
  std::filesystem::remove(err_path);
  return result;
}

}  // namespace bridgefit::testing
