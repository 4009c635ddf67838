// Placeholder until the issue that implements `bridgefit rcurve` lands: the
// subcommand exists and says so, with exit code 1.
#include "bridgefit/core/error.hpp"
#include "command.hpp"

namespace bridgefit::cli {
namespace {
class RcurveCommand final : public Command {
 public:
  const char* name() const override { return "rcurve"; }
  const char* description() const override { return "(not available in this version yet)"; }
  void Register(CLI::App& sub) override { sub.allow_extras(); }
  int Run(const CommonOptions&) override {
    throw Error(ErrorKind::kRuntime, "'bridgefit rcurve' is not available in this version yet");
  }
};
}  // namespace
std::unique_ptr<Command> MakeRcurveCommand() { return std::make_unique<RcurveCommand>(); }
}  // namespace bridgefit::cli
