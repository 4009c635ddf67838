// Placeholder until the issue that implements `bridgefit simulate` lands: the
// subcommand exists and says so, with exit code 1.
#include "bridgefit/core/error.hpp"
#include "command.hpp"

namespace bridgefit::cli {
namespace {
class SimulateCommand final : public Command {
 public:
  const char* name() const override { return "simulate"; }
  const char* description() const override { return "(not available in this version yet)"; }
  void Register(CLI::App& sub) override { sub.allow_extras(); }
  int Run(const CommonOptions&) override {
    throw Error(ErrorKind::kRuntime, "'bridgefit simulate' is not available in this version yet");
  }
};
}  // namespace
std::unique_ptr<Command> MakeSimulateCommand() { return std::make_unique<SimulateCommand>(); }
}  // namespace bridgefit::cli
