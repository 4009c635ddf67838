// `bridgefit report`: HTML page with gnuplot figures from a fit file.
//   bridgefit report fit.h5 --out out/mdf_ct
//   bridgefit report fit.h5 --out out/mdf_ct --record rcurve.h5 --dic dic.csv --truth scene.toml

#include <iostream>

#include "bridgefit/report/report.hpp"
#include "command.hpp"

namespace bridgefit::cli {
namespace {

class ReportCommand final : public Command {
 public:
  const char* name() const override { return "report"; }
  const char* description() const override {
    return "HTML report (index.html + PNG figures by gnuplot) of a fit file";
  }
  void Register(CLI::App& sub) override {
    sub.add_option("fit", fit_, "Fit file from 'bridgefit fit --out'")->required();
    sub.add_option("--out", out_, "Output folder (replaced if it exists)")->required();
    sub.add_option("--record", options_.record_h5,
                   "HDF5 with /experiment (bridgefit rcurve --out): load-displacement, crack length");
    sub.add_option("--dic", options_.dic_csv, "DIC per-frame CSV (bridgefit dic --csv)");
    sub.add_option("--truth", options_.truth_scene, "Scene TOML with the true law (synthetic tests)");
    sub.add_option("--title", options_.title, "Page title");
    sub.add_option("--gnuplot", options_.gnuplot, "gnuplot executable")->default_val("gnuplot");
  }
  int Run(const CommonOptions& common) override {
    const report::ReportSummary s = report::WriteFitReport(fit_, out_, options_);
    if (common.json) {
      PrintJson({{"index_html", s.index_html.string()},
                 {"figures", s.figures},
                 {"notes", s.notes},
                 {"wall_s", s.wall_s}});
    } else {
      std::cout << s.BriefReport() << "\n";
    }
    return 0;
  }

 private:
  std::string fit_, out_;
  report::ReportOptions options_;
};

}  // namespace

std::unique_ptr<Command> MakeReportCommand() { return std::make_unique<ReportCommand>(); }

}  // namespace bridgefit::cli
