#pragma once
// Subcommand plumbing of the `bridgefit` CLI. Each subcommand lives in its
// own apps/cmd_<name>.cpp and is created by a Make<Name>Command() factory
// listed in main.cpp.

#include <CLI/CLI.hpp>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bridgefit/core/units.hpp"

namespace bridgefit::inverse {
struct ParameterEstimate;
}

namespace bridgefit::cli {

// Options every subcommand has.
struct CommonOptions {
  bool json = false;  // stdout carries exactly one JSON object, nothing else
  bool quiet = false; // no progress on stderr
};

class Command {
 public:
  virtual ~Command() = default;
  virtual const char* name() const = 0;
  virtual const char* description() const = 0;
  // Adds the subcommand's own options to `sub`.
  virtual void Register(CLI::App& sub) = 0;
  // Runs after parsing. Returns the exit code; throws bridgefit::Error on
  // failure (mapped to exit 1, or 2 for ErrorKind::kUsage).
  virtual int Run(const CommonOptions& common) = 0;
};

std::unique_ptr<Command> MakeLawCommand();
std::unique_ptr<Command> MakeLawFreeCommand();
std::unique_ptr<Command> MakeSimulateCommand();
std::unique_ptr<Command> MakeRcurveCommand();
std::unique_ptr<Command> MakeDicCommand();
std::unique_ptr<Command> MakeCrackCommand();
std::unique_ptr<Command> MakeFitCommand();
std::unique_ptr<Command> MakeCampaignCommand();
std::unique_ptr<Command> MakeDesignCommand();
std::unique_ptr<Command> MakeReportCommand();  std::unique_ptr<Command> MakeSynthCommand();

// Prints one JSON object on stdout (the only stdout output under --json).
void PrintJson(const nlohmann::json& object);

// JSON null for a non-finite number, the number otherwise.
nlohmann::json NumberOrNull(double value);

// One fitted parameter as JSON (SI): value, total and statistical 95%
// intervals, model bias, bound, interval status (apps/fit_json.cpp; `fit` and
// `campaign` print the same object).
nlohmann::json EstimateJson(const inverse::ParameterEstimate& e);

// Parses `count` comma-separated numbers ("1.0,0.2,0.6"); anything else is
// a usage error (exit 2) naming the option.
std::vector<double> ParseOptionNumbers(const std::string& text, const char* option,
                                       std::size_t count);

// Parses a command-line quantity such as "0.45 MPa"; a bad value is a usage
// error (exit 2) naming the option. Empty text gives NaN.
double ParseOptionQuantity(const std::string& text, const Dimension& dimension,
                           const std::string& option);

}  // namespace bridgefit::cli
