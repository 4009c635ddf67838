// bridgefit: fracture tests with fibre bridging -> bridging-law parameters.
//
// Exit codes: 0 success, 1 runtime or data error (a corrupt HDF5 input too),
// 2 usage error, 130 / 143 interrupted by SIGINT / SIGTERM (no output written).
// Sample runs:
//   bridgefit law --law cubic --sigma-c "0.45 MPa" --jb "500 J/m^2" --jtip "2210 J/m^2"
//   bridgefit law --law linear --sigma-c 1MPa --delta-c 1mm --jtip 2210J/m^2 --json

#include <glog/logging.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <vector>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/input_limits.hpp"
#include "bridgefit/core/interrupt.hpp"
#include "bridgefit/core/version.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "command.hpp"

namespace bridgefit::cli {

void PrintJson(const nlohmann::json& object) { std::cout << object.dump(2) << std::endl; }

nlohmann::json NumberOrNull(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

std::vector<double> ParseOptionNumbers(const std::string& text, const char* option,
                                       std::size_t count) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    while (end && *end == ' ') ++end;
    if (end == item.c_str() || (end && *end != '\0') || !std::isfinite(v))
      throw Error(ErrorKind::kUsage, "not a number", {.field = option, .value = item});
    values.push_back(v);
  }
  if (values.size() != count)
    throw Error(ErrorKind::kUsage,
                "expected " + std::to_string(count) + " comma-separated numbers",
                {.field = option, .value = text});
  return values;
}

double ParseOptionQuantity(const std::string& text, const Dimension& dimension,
                           const std::string& option) {
  if (text.empty()) return NAN;
  try {
    return ParseQuantity(text, dimension);
  } catch (const Error& e) {
    const Error with_option = e.WithContext({.field = option});
    throw Error(ErrorKind::kUsage, with_option.message(), with_option.context());
  }
}

namespace {

// Every value given to a subcommand (positionals and options), in order.
std::vector<std::string> CommandLineValues(const CLI::App& sub) {
  std::vector<std::string> values;
  for (const CLI::Option* option : sub.get_options())
    for (const std::string& value : option->results()) values.push_back(value);
  return values;
}

// HDF5 files named on the command line are read first in a child process,
// so a file that crashes libhdf5 ends as "corrupt HDF5 file: FILE", exit 1.
void CheckHdf5Inputs(const std::vector<std::string>& values) {
  for (const std::string& value : values) {
    std::error_code ec;
    if (value.empty() || !std::filesystem::is_regular_file(value, ec)) continue;
    if (io::HasHdf5Signature(value)) io::CheckH5FileInChildProcess(value);
  }
}

}  // namespace
}  // namespace bridgefit::cli

int main(int argc, char** argv) {
  using namespace bridgefit;
  // OpenCV checks an image header against this before decoding: our pixel limit.
  try {
    const InputLimits limits = InputLimits::FromEnvironment();
    setenv("OPENCV_IO_MAX_IMAGE_PIXELS", std::to_string(limits.max_image_pixels).c_str(), 0);
  } catch (const Error& e) {
    std::cerr << "bridgefit: error: " << e.what() << "\n";
    return 2;
  }
  // Before any thread exists: SIGINT / SIGTERM go to the watcher thread only.
  InterruptWatchOptions interrupt_options;
  {
    std::string what = "bridgefit";
    for (int i = 1; i < argc && i < 8; ++i) what += std::string(" ") + argv[i];
    if (argc > 8) what += " ...";
    interrupt_options.what = what;
    for (int i = 1; i < argc; ++i) interrupt_options.outputs.emplace_back(argv[i]);
  }
  StartInterruptWatcher(interrupt_options);
  // Ceres logs through glog; a failed evaluation inside a fit is reported in
  // the fit summary, so its internal messages are not shown.
  FLAGS_minloglevel = google::GLOG_FATAL;
  CLI::App app{"bridgefit: R curves and bridging laws from fracture tests of fibrous materials"};
  app.set_version_flag("--version", std::string("bridgefit ") + VersionString());
  app.require_subcommand(1);
  app.failure_message(CLI::FailureMessage::help);

  cli::CommonOptions common;
  std::vector<std::unique_ptr<cli::Command>> commands;
  commands.push_back(cli::MakeLawCommand());
  commands.push_back(cli::MakeLawFreeCommand());
  commands.push_back(cli::MakeSimulateCommand());
  commands.push_back(cli::MakeRcurveCommand());
  commands.push_back(cli::MakeDicCommand());
  commands.push_back(cli::MakeCrackCommand());
  commands.push_back(cli::MakeFitCommand());
  commands.push_back(cli::MakeCampaignCommand());
  commands.push_back(cli::MakeDesignCommand());
  commands.push_back(cli::MakeReportCommand()); commands.push_back(cli::MakeSynthCommand());

  std::vector<CLI::App*> subs;
  for (auto& command : commands) {
    CLI::App* sub = app.add_subcommand(command->name(), command->description());
    sub->add_flag("--json", common.json, "Print exactly one JSON object on stdout (SI units)");
    sub->add_flag("--quiet", common.quiet, "No progress messages on stderr");
    command->Register(*sub);
    subs.push_back(sub);
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help/version (0) or the usage error
    return code == 0 ? 0 : 2;
  }

  for (size_t i = 0; i < commands.size(); ++i) {
    if (!subs[i]->parsed()) continue;
    try {
      cli::CheckHdf5Inputs(cli::CommandLineValues(*subs[i]));
      return commands[i]->Run(common);
    } catch (const Error& e) {
      if (e.kind() == ErrorKind::kInterrupted) {
        std::cerr << "bridgefit " << commands[i]->name() << ": " << e.what()
                  << " Stopped; no output written.\n";
        return 128 + InterruptSignal();
      }
      std::cerr << "bridgefit " << commands[i]->name() << ": error: " << e.what() << "\n";
      return e.kind() == ErrorKind::kUsage ? 2 : 1;
    } catch (const std::exception& e) {
      std::cerr << "bridgefit " << commands[i]->name() << ": error: " << e.what() << "\n";
      return 1;
    }
  }
  return 2;
}
